#include "bake/bake.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <map>
#include <optional>

#include "bake/corner_normals.h"
#include "bake/dilate.h"
#include "bake/document_impl.h"
#include "bake/gltf_access.h"
#include "bake/texel_receivers.h"
#include "bake/vertex_output.h"
#include "bake/box_atlas.h"
#include "bake/uv_choice.h"
#include "bake/uv_rewrite.h"

namespace exao::bake {

Result<void> check_options(const BakeOptions& o) {
  if (o.target == Target::Vertex) return {};
  if (o.texture_size < 16 || o.texture_size > 16384) {
    return fail("texture_size: the map size must be from 16 to 16384 texels, got " + std::to_string(o.texture_size));
  }
  const int k = static_cast<int>(std::lround(std::sqrt(static_cast<double>(o.texel_samples))));
  if (o.texel_samples < 1 || o.texel_samples > 256 || k * k != o.texel_samples) {
    return fail("texel_samples: must be a square number from 1 to 256 (1, 4, 9, 16...), got " +
                std::to_string(o.texel_samples));
  }
  if (o.margin < 0 || o.margin > 64) return fail("margin: must be from 0 to 64 texels, got " + std::to_string(o.margin));
  if (o.uv_set < 0 || o.uv_set > 15) return fail("uv_set: must be from 0 to 15, got " + std::to_string(o.uv_set));
  return {};
}

namespace {

// The receivers' AO from the engine (which batches, orders and threads them), timed.
Result<void> compute(BakeResult& result, const engine::Engine& engine, const engine::RunOptions& run) {
  const auto start = std::chrono::steady_clock::now();
  Result<std::vector<float>> values = engine.ao(result.receivers, run);
  if (!values) return std::unexpected(values.error());
  result.ao = std::move(*values);
  result.ao_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return {};
}

const tinygltf::Primitive& gltf_primitive(const tinygltf::Model& model, const MeshPrimitive& prim) {
  return model.meshes[static_cast<std::size_t>(prim.mesh)].primitives[static_cast<std::size_t>(prim.primitive)];
}

std::string primitive_label(const tinygltf::Model& model, const MeshPrimitive& prim) {
  return mesh_label(model, prim.mesh) + " primitive " + std::to_string(prim.primitive);
}

// Front-face corners of a part, as the scene has them.
std::vector<std::uint32_t> part_corners(const ModelWalk& walk, std::size_t part) {
  const MeshPrimitive& prim = walk.primitives[static_cast<std::size_t>(walk.parts[part].primitive)];
  std::vector<std::uint32_t> out(prim.corners.size());
  for (std::size_t t = 0; t < prim.corners.size() / 3; ++t) {
    const auto c = walk.corners(part, t);
    std::copy(c.begin(), c.end(), out.begin() + static_cast<std::ptrdiff_t>(3 * t));
  }
  return out;
}

// The file's NORMALs of a part in world space (the inverse transpose of the node's matrix), or
// an empty vector when the primitive has none.
Result<std::vector<glm::vec3>> file_normals(const tinygltf::Model& model, const ModelWalk& walk, std::size_t part) {
  const Part& p = walk.parts[part];
  const MeshPrimitive& prim = walk.primitives[static_cast<std::size_t>(p.primitive)];
  const tinygltf::Primitive& gp = gltf_primitive(model, prim);
  const auto found = gp.attributes.find("NORMAL");
  if (found == gp.attributes.end()) return std::vector<glm::vec3>{};
  auto values = read_accessor(model, found->second, 3, kNormalTypes, true, primitive_label(model, prim) + " NORMAL");
  if (!values) return std::unexpected(values.error());
  if (values->size() != 3 * prim.positions.size()) {
    return fail(primitive_label(model, prim) + ": NORMAL has a different count than POSITION");
  }
  const glm::dmat3 m = glm::transpose(glm::inverse(glm::dmat3(walk.instances[static_cast<std::size_t>(p.instance)].world)));
  std::vector<glm::vec3> out(prim.positions.size());
  for (std::size_t v = 0; v < out.size(); ++v) {
    const glm::dvec3 n = m * glm::dvec3((*values)[3 * v], (*values)[3 * v + 1], (*values)[3 * v + 2]);
    const double length = glm::length(n);
    out[v] = length > 0.0 && std::isfinite(length) ? glm::vec3(n / length) : glm::vec3(0.0f);
  }
  return out;
}

// `engine` null: only the receivers (bake_receivers).
Result<BakeResult> bake_vertices(Document& document, const BakeOptions& options, const engine::Engine* engine,
                                 const engine::RunOptions& run) {
  Document::Impl& doc = document.impl();
  const ModelWalk& walk = doc.walk;
  BakeResult result;
  result.target = Target::Vertex;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> where;  // per receiver: part, vertex
  std::size_t without_file_normals = 0;
  for (std::size_t p = 0; p < walk.parts.size(); ++p) {
    const std::vector<glm::vec3>& world = walk.parts[p].world;
    const bool two_sided = walk.primitives[static_cast<std::size_t>(walk.parts[p].primitive)].two_sided;
    std::vector<glm::vec3> normals = vertex_normals(world, part_corners(walk, p), two_sided);
    if (options.normals == NormalSource::File) {
      auto from_file = file_normals(doc.model, walk, p);
      if (!from_file) return std::unexpected(from_file.error());
      if (from_file->empty()) {
        ++without_file_normals;
      } else {
        // A vertex no triangle uses stays without a receiver; a broken file normal falls back.
        for (std::size_t v = 0; v < normals.size(); ++v) {
          if (normals[v] != glm::vec3(0.0f) && (*from_file)[v] != glm::vec3(0.0f)) normals[v] = (*from_file)[v];
        }
      }
    }
    for (std::size_t v = 0; v < world.size(); ++v) {
      if (normals[v] == glm::vec3(0.0f)) continue;  // no triangle with area uses it: nothing to receive
      result.receivers.push_back({world[v], normals[v], static_cast<std::uint64_t>(result.receivers.size())});
      where.emplace_back(static_cast<std::uint32_t>(p), static_cast<std::uint32_t>(v));
    }
  }
  if (without_file_normals > 0) {
    result.notes.push_back(std::to_string(without_file_normals) +
                           " primitive(s) have no NORMAL: their receivers use geometric normals");
  }
  if (engine == nullptr) return result;
  if (auto ok = compute(result, *engine, run); !ok) return std::unexpected(ok.error());
  result.part_vertex_ao.resize(walk.parts.size());
  for (std::size_t p = 0; p < walk.parts.size(); ++p) result.part_vertex_ao[p].assign(walk.parts[p].world.size(), 1.0f);
  for (std::size_t r = 0; r < where.size(); ++r) result.part_vertex_ao[where[r].first][where[r].second] = result.ao[r];
  auto split = write_vertex_ao(doc.model, walk, result.part_vertex_ao, options.channel, result.notes);
  if (!split) return std::unexpected(split.error());
  result.meshes_split = *split;
  return result;
}

// A primitive's UV set `set` per vertex as stored (normalised integers decoded), or nothing when
// the primitive has no such set.
Result<std::optional<std::vector<glm::dvec2>>> read_uv_set(const tinygltf::Model& model, const MeshPrimitive& prim, int set) {
  const std::string name = "TEXCOORD_" + std::to_string(set);
  const tinygltf::Primitive& gp = gltf_primitive(model, prim);
  const auto found = gp.attributes.find(name);
  if (found == gp.attributes.end()) return std::optional<std::vector<glm::dvec2>>{};
  const std::string label = primitive_label(model, prim);
  auto values = read_accessor(model, found->second, 2, kTexcoordTypes, true, label + " " + name);
  if (!values) return std::unexpected(values.error());
  if (values->size() != 2 * prim.positions.size()) return fail(label + ": " + name + " has a different count than POSITION");
  std::vector<glm::dvec2> uv(prim.positions.size());
  for (std::size_t v = 0; v < uv.size(); ++v) uv[v] = glm::dvec2((*values)[2 * v], (*values)[2 * v + 1]);
  return std::optional<std::vector<glm::dvec2>>(std::move(uv));
}

// The highest TEXCOORD_k a glTF primitive has, plus one.
int texcoord_sets(const tinygltf::Primitive& prim) {
  int sets = 0;
  for (const auto& [name, accessor] : prim.attributes) {
    if (name.rfind("TEXCOORD_", 0) != 0) continue;
    try {
      sets = std::max(sets, std::stoi(name.substr(9)) + 1);
    } catch (const std::exception&) {
    }
  }
  return sets;
}

std::string percent(double share) {
  char text[32];
  std::snprintf(text, sizeof text, share > 0.0 && share < 0.001 ? "%.2f%%" : "%.1f%%", 100.0 * share);
  return text;
}

std::string node_label(const tinygltf::Model& model, int node) {
  const std::string& name = model.nodes[static_cast<std::size_t>(node)].name;
  return name.empty() ? "node " + std::to_string(node) : "node '" + name + "'";
}

// Why two parts overlap, in words.
std::string overlap_reason(const tinygltf::Model& model, const ModelWalk& walk, std::uint32_t a, std::uint32_t b) {
  const Part& pa = walk.parts[a];
  const Part& pb = walk.parts[b];
  const MeshInstance& ia = walk.instances[static_cast<std::size_t>(pa.instance)];
  const MeshInstance& ib = walk.instances[static_cast<std::size_t>(pb.instance)];
  if (a == b) {
    return primitive_label(model, walk.primitives[static_cast<std::size_t>(pa.primitive)]) +
           " maps several of its triangles to the same texels (mirrored or stacked UVs)";
  }
  if (pa.primitive == pb.primitive) {
    return mesh_label(model, ia.mesh) + " is drawn by " + node_label(model, ia.node) + " and " +
           (ia.node == ib.node ? "again by the same node (GPU instancing)" : node_label(model, ib.node));
  }
  return primitive_label(model, walk.primitives[static_cast<std::size_t>(pa.primitive)]) + " and " +
         primitive_label(model, walk.primitives[static_cast<std::size_t>(pb.primitive)]) + " share UV space";
}

// `engine` null: only the receivers (bake_receivers), the document left as it was.
Result<BakeResult> bake_texture(Document& document, const BakeOptions& options, const engine::Engine* engine,
                                const engine::RunOptions& run) {
  Document::Impl& doc = document.impl();
  tinygltf::Model& model = doc.model;
  const ModelWalk& walk = doc.walk;
  BakeResult result;
  result.target = Target::Texture;
  const int size = options.texture_size;

  // Where each primitive's AO UVs come from (--uv): the file's set, seen through the transform
  // of the texture slot the AO shares, or a generated chart atlas. Decided once per primitive.
  struct PrimitiveUv {
    bool used = false;
    bool generated = false;
    AoSlot slot;
    std::string decision;                  // for the notes
    std::vector<glm::dvec2> corner_uv;     // per primitive corner (prim.corners order), texture space
    std::vector<glm::vec2> vertex_uv;      // file: per vertex, clamped; generated: per new vertex
    std::vector<std::uint32_t> source;     // generated: new vertex -> old vertex
    std::vector<std::uint32_t> corners;    // generated: per primitive corner, the new vertex
    int set = 0;                           // generated: the TEXCOORD_<set> written
  };
  std::vector<PrimitiveUv> prim_uv(walk.primitives.size());
  std::vector<int> first_part(walk.primitives.size(), -1);
  for (std::size_t p = 0; p < walk.parts.size(); ++p) {
    const auto i = static_cast<std::size_t>(walk.parts[p].primitive);
    prim_uv[i].used = true;
    if (first_part[i] < 0) first_part[i] = static_cast<int>(p);
  }
  const int measure_resolution = std::min(size, 1024);
  for (std::size_t i = 0; i < walk.primitives.size(); ++i) {
    PrimitiveUv& u = prim_uv[i];
    if (!u.used) continue;
    const MeshPrimitive& prim = walk.primitives[i];
    u.slot = ao_slot(model, prim.material, options.uv_set);
    const std::string set_name = "TEXCOORD_" + std::to_string(u.slot.set);
    if (options.uv == UvMode::Generate) {
      u.generated = true;
      u.decision = "uv = generate";
      continue;
    }
    auto read = read_uv_set(model, prim, u.slot.set);
    if (!read) return std::unexpected(read.error());
    if (!*read) {
      if (options.uv == UvMode::File) {
        return fail(primitive_label(model, prim) + " has no " + set_name +
                    ": a texture bake needs UVs; bake per vertex instead, or use uv = auto or generate" +
                    (options.uv_set == 0 ? std::string() : ", or choose another UV set"));
      }
      u.generated = true;
      u.decision = "has no " + set_name;
      continue;
    }
    std::vector<glm::dvec2>& uv = **read;
    for (glm::dvec2& t : uv) t = glm::dvec2(u.slot.matrix * glm::dvec3(t, 1.0));
    u.corner_uv.resize(prim.corners.size());
    std::vector<glm::vec3> corner_world(prim.corners.size());
    const Part& part = walk.parts[static_cast<std::size_t>(first_part[i])];
    for (std::size_t c = 0; c < prim.corners.size(); ++c) {
      u.corner_uv[c] = uv[prim.corners[c]];
      corner_world[c] = part.world[prim.corners[c]];
    }
    const UvFigures figures = measure_uvs(u.corner_uv, corner_world, measure_resolution);
    const std::string reason = unusable_reason(figures);
    const std::string through = u.slot.has_transform ? " through the KHR_texture_transform of its " + u.slot.name : "";
    if (options.uv == UvMode::File && figures.outside_share > 0.0) {
      char range[160];
      std::snprintf(range, sizeof range, "(%.3g, %.3g) to (%.3g, %.3g)", figures.lo.x, figures.lo.y, figures.hi.x, figures.hi.y);
      return fail(primitive_label(model, prim) + ": " + set_name + through + " runs from " + range +
                  ", outside [0, 1]; an AO map needs every triangle inside the texture (tiling UVs cannot hold AO): "
                  "bake per vertex instead, or use uv = auto or generate");
    }
    if (options.uv == UvMode::Auto && !reason.empty()) {
      u.generated = true;
      u.decision = set_name + through + " " + reason;
      continue;
    }
    u.decision = set_name + through + " used (" + percent(figures.uv_area) + " of the map, " +
                 percent(figures.overlap_share) + " self-overlap)";
    if (!reason.empty()) u.decision += "; it " + reason + ": its AO will be wrong there (uv = auto or generate fixes it)";
    u.vertex_uv.resize(uv.size());
    for (std::size_t v = 0; v < uv.size(); ++v) {
      u.vertex_uv[v] = glm::clamp(glm::vec2(uv[v]), glm::vec2(0.0f), glm::vec2(1.0f));
    }
    for (glm::dvec2& t : u.corner_uv) t = glm::clamp(t, glm::dvec2(0.0), glm::dvec2(1.0));
  }

  // One map per material, and a separate one for a material's primitives with generated UVs
  // (they get a copy of the material, since one occlusionTexture reads one set).
  std::map<std::pair<int, bool>, int> map_of_key;
  std::vector<bool> map_generated;
  result.part_map.assign(walk.parts.size(), -1);
  for (std::size_t p = 0; p < walk.parts.size(); ++p) {
    const auto i = static_cast<std::size_t>(walk.parts[p].primitive);
    const std::pair<int, bool> key{walk.primitives[i].material, prim_uv[i].generated};
    auto [it, added] = map_of_key.try_emplace(key, static_cast<int>(result.maps.size()));
    if (added) {
      AoMap map;
      map.material = key.first;
      map.size = size;
      result.maps.push_back(std::move(map));
      map_generated.push_back(key.second);
    }
    result.part_map[p] = it->second;
  }
  if (result.maps.size() > 1) {
    for (std::size_t m = 0; m < result.maps.size(); ++m) {
      AoMap& map = result.maps[m];
      map.label = (map.material >= 0 ? "m" + std::to_string(map.material) : "default") + (map_generated[m] ? "-uv" : "");
    }
  }

  // Generated UVs: one box-projection chart atlas per map, over the world-space triangles (as
  // the first node that draws each primitive places them), so texel density is even across it.
  std::vector<std::string> atlas_figures(result.maps.size());
  for (std::size_t m = 0; m < result.maps.size(); ++m) {
    if (!map_generated[m]) continue;
    std::vector<std::size_t> members;
    for (std::size_t i = 0; i < walk.primitives.size(); ++i) {
      if (prim_uv[i].used && prim_uv[i].generated && walk.primitives[i].material == result.maps[m].material) members.push_back(i);
    }
    std::vector<glm::vec3> positions;
    std::vector<std::uint32_t> triangles;
    std::vector<std::size_t> vertex_base, corner_base;
    int set = 0;
    for (const std::size_t i : members) {
      const Part& part = walk.parts[static_cast<std::size_t>(first_part[i])];
      vertex_base.push_back(positions.size());
      corner_base.push_back(triangles.size());
      for (const std::uint32_t c : walk.primitives[i].corners) triangles.push_back(static_cast<std::uint32_t>(positions.size()) + c);
      positions.insert(positions.end(), part.world.begin(), part.world.end());
      set = std::max(set, texcoord_sets(gltf_primitive(model, walk.primitives[i])));
    }
    auto atlas = box_atlas(positions, triangles, size, 2 * options.margin + 2);
    if (!atlas) return std::unexpected(atlas.error());
    char figures[128];
    std::snprintf(figures, sizeof figures, "generated TEXCOORD_%d: %zu charts at %.3g texels per unit", set, atlas->charts,
                  static_cast<double>(atlas->texels_per_unit));
    atlas_figures[m] = figures;
    for (std::size_t k = 0; k < members.size(); ++k) {
      PrimitiveUv& u = prim_uv[members[k]];
      u.set = set;
      const std::size_t corner_count = walk.primitives[members[k]].corners.size();
      std::map<std::uint32_t, std::uint32_t> local;  // atlas vertex -> new vertex of this primitive
      u.corners.resize(corner_count);
      u.corner_uv.resize(corner_count);
      for (std::size_t c = 0; c < corner_count; ++c) {
        const std::uint32_t a = atlas->triangles[corner_base[k] + c];
        auto [it, added] = local.try_emplace(a, static_cast<std::uint32_t>(u.source.size()));
        if (added) {
          u.source.push_back(atlas->source_vertex[a] - static_cast<std::uint32_t>(vertex_base[k]));
          u.vertex_uv.push_back(atlas->uv[a]);
        }
        u.corners[c] = it->second;
        u.corner_uv[c] = glm::dvec2(atlas->uv[a]);
      }
    }
  }

  // The decisions, one line per mesh.
  {
    std::map<int, std::string> per_mesh;
    std::vector<int> mesh_order;
    for (std::size_t i = 0; i < walk.primitives.size(); ++i) {
      const PrimitiveUv& u = prim_uv[i];
      if (!u.used) continue;
      const MeshPrimitive& prim = walk.primitives[i];
      std::string line = "primitive " + std::to_string(prim.primitive) + ": " + u.decision;
      if (u.generated) {
        for (std::size_t m = 0; m < result.maps.size(); ++m) {
          if (map_generated[m] && result.maps[m].material == prim.material) line += " -> " + atlas_figures[m];
        }
      }
      auto [it, added] = per_mesh.try_emplace(prim.mesh, line);
      if (added) {
        mesh_order.push_back(prim.mesh);
      } else {
        it->second += "; " + line;
      }
    }
    for (const int mesh : mesh_order) result.notes.push_back("AO UVs of " + mesh_label(model, mesh) + ": " + per_mesh[mesh]);
  }

  // Per part: UVs per vertex (file sets) and per corner in front-face order (all).
  result.part_uv.resize(walk.parts.size());
  result.part_corner_uv.resize(walk.parts.size());
  for (std::size_t p = 0; p < walk.parts.size(); ++p) {
    const PrimitiveUv& u = prim_uv[static_cast<std::size_t>(walk.parts[p].primitive)];
    if (!u.generated) result.part_uv[p] = u.vertex_uv;
    const bool mirrored = walk.instances[static_cast<std::size_t>(walk.parts[p].instance)].mirrored;
    std::vector<glm::vec2>& out = result.part_corner_uv[p];
    out.resize(u.corner_uv.size());
    for (std::size_t t = 0; t + 2 < u.corner_uv.size(); t += 3) {
      // walk.corners() swaps the last two corners of a mirrored instance's triangles.
      out[t] = glm::vec2(u.corner_uv[t]);
      out[t + 1] = glm::vec2(u.corner_uv[mirrored ? t + 2 : t + 1]);
      out[t + 2] = glm::vec2(u.corner_uv[mirrored ? t + 1 : t + 2]);
    }
  }

  // Receiver normals per triangle corner: crease-aware geometric ones, or the file's.
  std::vector<glm::vec3> corner_positions;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> corner_source;  // part, vertex
  for (std::size_t p = 0; p < walk.parts.size(); ++p) {
    for (const std::uint32_t v : part_corners(walk, p)) {
      corner_positions.push_back(walk.parts[p].world[v]);
      corner_source.emplace_back(static_cast<std::uint32_t>(p), v);
    }
  }
  std::vector<glm::vec3> normals = corner_normals(corner_positions, kCreaseDegrees);
  if (options.normals == NormalSource::File) {
    std::size_t without = 0;
    std::map<std::uint32_t, std::vector<glm::vec3>> per_part;
    for (std::size_t p = 0; p < walk.parts.size(); ++p) {
      auto from_file = file_normals(model, walk, p);
      if (!from_file) return std::unexpected(from_file.error());
      if (from_file->empty()) ++without;
      per_part[static_cast<std::uint32_t>(p)] = std::move(*from_file);
    }
    for (std::size_t c = 0; c < normals.size(); ++c) {
      const std::vector<glm::vec3>& n = per_part[corner_source[c].first];
      if (!n.empty() && n[corner_source[c].second] != glm::vec3(0.0f)) normals[c] = n[corner_source[c].second];
    }
    if (without > 0) {
      result.notes.push_back(std::to_string(without) + " primitive(s) have no NORMAL: their texels use geometric normals");
    }
  }

  // Texel receivers, map by map.
  const int k = static_cast<int>(std::lround(std::sqrt(static_cast<double>(options.texel_samples))));
  std::vector<TexelReceivers> texels(result.maps.size());
  for (std::size_t m = 0; m < result.maps.size(); ++m) {
    std::vector<UvTriangle> triangles;
    std::size_t corner = 0;
    for (std::size_t p = 0; p < walk.parts.size(); ++p) {
      const std::vector<std::uint32_t> corners = part_corners(walk, p);
      if (result.part_map[p] != static_cast<int>(m)) {
        corner += corners.size();
        continue;
      }
      for (std::size_t t = 0; t + 2 < corners.size(); t += 3, corner += 3) {
        UvTriangle tri;
        for (std::size_t j = 0; j < 3; ++j) {
          tri.uv[j] = glm::dvec2(result.part_corner_uv[p][t + j]) * static_cast<double>(size);
          tri.position[j] = walk.parts[p].world[corners[t + j]];
          tri.normal[j] = normals[corner + j];
        }
        tri.source = static_cast<std::uint32_t>(p);
        triangles.push_back(tri);
      }
    }
    texels[m] = texel_receivers(triangles, size, size, k, result.receivers.size());
    AoMap& map = result.maps[m];
    map.covered_texels = texels[m].covered_texels;
    map.overlap_texels = texels[m].overlap_texels;
    result.receivers.insert(result.receivers.end(), texels[m].receivers.begin(), texels[m].receivers.end());
    result.receiver_texel.insert(result.receiver_texel.end(), texels[m].texel.begin(), texels[m].texel.end());
    result.receiver_map.insert(result.receiver_map.end(), texels[m].receivers.size(), static_cast<std::uint32_t>(m));
    texels[m].receivers = {};
  }

  if (engine == nullptr) return result;
  if (auto ok = compute(result, *engine, run); !ok) return std::unexpected(ok.error());

  // Each texel is the mean of its receivers; then the margin.
  const std::size_t texel_count = static_cast<std::size_t>(size) * static_cast<std::size_t>(size);
  std::vector<std::vector<std::uint32_t>> counts(result.maps.size());
  for (std::size_t m = 0; m < result.maps.size(); ++m) {
    result.maps[m].ao.assign(texel_count, 0.0f);
    counts[m].assign(texel_count, 0);
  }
  for (std::size_t r = 0; r < result.ao.size(); ++r) {
    result.maps[result.receiver_map[r]].ao[result.receiver_texel[r]] += result.ao[r];
    ++counts[result.receiver_map[r]][result.receiver_texel[r]];
  }
  for (std::size_t m = 0; m < result.maps.size(); ++m) {
    AoMap& map = result.maps[m];
    map.filled = texels[m].covered;
    for (std::size_t i = 0; i < texel_count; ++i) {
      if (counts[m][i] > 0) map.ao[i] /= static_cast<float>(counts[m][i]);
    }
    // Uncovered texels read as open (1): no occlusion where nothing is mapped.
    dilate(map.ao, map.filled, size, size, options.margin, 1.0f);
    const std::string which = map.label.empty() ? "the AO map" : "AO map " + map.label;
    if (map.covered_texels == 0) {
      result.notes.push_back(which + " covers no texel: its UVs have no area, so it holds no AO (it reads as open); "
                             "bake with uv = generate, or per vertex");
    }
    if (map.overlap_texels > 0) {
      std::string reasons;
      for (const auto& pair : texels[m].overlap_examples) {
        const std::string reason = overlap_reason(model, walk, pair[0], pair[1]);
        if (reasons.find(reason) == std::string::npos) reasons += (reasons.empty() ? "" : "; ") + reason;
      }
      result.notes.push_back(which + ": " + std::to_string(map.overlap_texels) +
                             " texels are covered by overlapping UVs" + (reasons.empty() ? "" : " (" + reasons + ")") +
                             ": they hold the mean AO of every surface mapped there");
    }
  }

  // The maps into the model: one image, texture and sampler each; the image's bytes come at save.
  tinygltf::Sampler sampler;
  sampler.name = "exao AO";
  sampler.magFilter = TINYGLTF_TEXTURE_FILTER_LINEAR;
  sampler.minFilter = TINYGLTF_TEXTURE_FILTER_LINEAR_MIPMAP_LINEAR;
  sampler.wrapS = sampler.wrapT = TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE;
  model.samplers.push_back(sampler);
  const int sampler_index = static_cast<int>(model.samplers.size() - 1);
  for (AoMap& map : result.maps) {
    tinygltf::Image image;
    image.name = doc.name + " AO" + (map.label.empty() ? "" : " " + map.label);
    image.mimeType = "image/png";
    model.images.push_back(image);
    map.image = static_cast<int>(model.images.size() - 1);
    tinygltf::Texture texture;
    texture.name = image.name;
    texture.source = map.image;
    texture.sampler = sampler_index;
    model.textures.push_back(texture);
    const int texture_index = static_cast<int>(model.textures.size() - 1);
    int material = map.material;
    if (material < 0) {
      // glTF's default material, made explicit so that it can carry the map: single-sided, white.
      tinygltf::Material made;
      made.name = "exao default material";
      model.materials.push_back(made);
      material = static_cast<int>(model.materials.size() - 1);
      for (std::size_t p = 0; p < walk.parts.size(); ++p) {
        if (result.part_map[p] != &map - result.maps.data()) continue;
        const MeshPrimitive& prim = walk.primitives[static_cast<std::size_t>(walk.parts[p].primitive)];
        model.meshes[static_cast<std::size_t>(prim.mesh)].primitives[static_cast<std::size_t>(prim.primitive)].material = material;
      }
      result.notes.push_back("primitives without a material got one (glTF's default) to carry the AO map");
    }
    const std::size_t map_index = static_cast<std::size_t>(&map - result.maps.data());
    const bool generated = map_generated[map_index];
    if (generated && map.material >= 0 && map_of_key.count({map.material, false}) != 0) {
      // The material also carries a map on file UVs: the generated primitives get a copy.
      tinygltf::Material copy = model.materials[static_cast<std::size_t>(material)];
      copy.name += copy.name.empty() ? "exao AO UV set" : " (exao AO UV set)";
      model.materials.push_back(std::move(copy));
      material = static_cast<int>(model.materials.size() - 1);
      for (std::size_t p = 0; p < walk.parts.size(); ++p) {
        if (result.part_map[p] != static_cast<int>(map_index)) continue;
        const MeshPrimitive& prim = walk.primitives[static_cast<std::size_t>(walk.parts[p].primitive)];
        model.meshes[static_cast<std::size_t>(prim.mesh)].primitives[static_cast<std::size_t>(prim.primitive)].material = material;
      }
      result.notes.push_back("material " + std::to_string(map.material) +
                             " is shared by primitives on file and generated UVs: a copy carries the generated UVs' map");
    }
    tinygltf::Material& target = model.materials[static_cast<std::size_t>(material)];
    if (target.occlusionTexture.index >= 0) {
      result.notes.push_back("material " + (target.name.empty() ? std::to_string(material) : "'" + target.name + "'") +
                             " had an occlusionTexture: the baked map replaces it");
    }
    target.occlusionTexture.index = texture_index;
    target.occlusionTexture.strength = 1.0;
    target.occlusionTexture.extensions.erase("KHR_texture_transform");
    int set = options.uv_set;
    for (std::size_t i = 0; i < walk.primitives.size(); ++i) {
      const PrimitiveUv& u = prim_uv[i];
      if (!u.used || u.generated != generated || walk.primitives[i].material != map.material) continue;
      if (generated) {
        set = u.set;
      } else if (u.slot.has_transform) {
        // The map is laid out in the slot's transformed space, so it reads through the same transform.
        target.occlusionTexture.extensions["KHR_texture_transform"] = u.slot.transform;
      }
      break;
    }
    target.occlusionTexture.texCoord = set;
  }
  for (std::size_t i = 0; i < walk.primitives.size(); ++i) {
    const PrimitiveUv& u = prim_uv[i];
    if (!u.used || !u.generated) continue;
    const MeshPrimitive& prim = walk.primitives[i];
    if (auto ok = write_generated_uvs(model, prim.mesh, prim.primitive, u.source, u.vertex_uv, u.corners, u.set,
                                      primitive_label(model, prim));
        !ok) {
      return std::unexpected(ok.error());
    }
  }
  return result;
}

Result<BakeResult> run_bake(Document& document, const BakeOptions& options, const engine::Engine* engine,
                            const engine::RunOptions& run) {
  if (auto ok = check_options(options); !ok) return std::unexpected(ok.error());
  Result<BakeResult> result = options.target == Target::Vertex ? bake_vertices(document, options, engine, run)
                                                               : bake_texture(document, options, engine, run);
  // What fails past the options is about the input: the message names it.
  if (!result) return fail((document.from_gltf() ? document.impl().source_path : document.name()) + ": " + result.error().message);
  return result;
}

}  // namespace

Result<BakeResult> bake(Document& document, const BakeOptions& options, const engine::Engine& engine,
                        const ProgressCallback& progress) {
  engine::RunOptions run;
  run.progress = progress;
  return run_bake(document, options, &engine, run);
}

Result<BakeResult> bake(Document& document, const BakeOptions& options, const engine::Engine& engine,
                        const engine::RunOptions& run) {
  return run_bake(document, options, &engine, run);
}

Result<std::vector<Receiver>> bake_receivers(Document& document, const BakeOptions& options) {
  Result<BakeResult> result = run_bake(document, options, nullptr, {});
  if (!result) return std::unexpected(result.error());
  return std::move(result->receivers);
}

}  // namespace exao::bake
