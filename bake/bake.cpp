#include "bake/bake.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>

#include "bake/corner_normals.h"
#include "bake/dilate.h"
#include "bake/document_impl.h"
#include "bake/gltf_access.h"
#include "bake/texel_receivers.h"
#include "bake/vertex_output.h"

namespace exao::bake {
namespace {

// UVs this far outside [0, 1] are rounding of an edge on the border, and are clamped.
constexpr double kUvSlack = 1e-3;

}  // namespace

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
Result<void> compute(BakeResult& result, const engine::Engine& engine, const ProgressCallback& progress) {
  const auto start = std::chrono::steady_clock::now();
  engine::RunOptions run;
  run.progress = progress;
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

Result<BakeResult> bake_vertices(Document& document, const BakeOptions& options, const engine::Engine& engine,
                                 const ProgressCallback& progress) {
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
  if (auto ok = compute(result, engine, progress); !ok) return std::unexpected(ok.error());
  result.part_vertex_ao.resize(walk.parts.size());
  for (std::size_t p = 0; p < walk.parts.size(); ++p) result.part_vertex_ao[p].assign(walk.parts[p].world.size(), 1.0f);
  for (std::size_t r = 0; r < where.size(); ++r) result.part_vertex_ao[where[r].first][where[r].second] = result.ao[r];
  auto split = write_vertex_ao(doc.model, walk, result.part_vertex_ao, options.channel, result.notes);
  if (!split) return std::unexpected(split.error());
  result.meshes_split = *split;
  return result;
}

// The UV set of a primitive, checked to lie in [0, 1] wherever a triangle uses it.
Result<std::vector<glm::vec2>> read_uvs(const tinygltf::Model& model, const MeshPrimitive& prim, int uv_set) {
  const std::string name = "TEXCOORD_" + std::to_string(uv_set);
  const tinygltf::Primitive& gp = gltf_primitive(model, prim);
  const auto found = gp.attributes.find(name);
  const std::string label = primitive_label(model, prim);
  if (found == gp.attributes.end()) {
    return fail(label + " has no " + name + ": a texture bake needs UVs; bake per vertex instead" +
                (uv_set == 0 ? std::string() : " or choose another UV set"));
  }
  auto values = read_accessor(model, found->second, 2, kTexcoordTypes, true, label + " " + name);
  if (!values) return std::unexpected(values.error());
  if (values->size() != 2 * prim.positions.size()) return fail(label + ": " + name + " has a different count than POSITION");
  std::vector<glm::vec2> uv(prim.positions.size());
  glm::dvec2 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
  for (const std::uint32_t v : prim.corners) {
    const glm::dvec2 t((*values)[2 * v], (*values)[2 * v + 1]);
    lo = glm::min(lo, t);
    hi = glm::max(hi, t);
  }
  if (!prim.corners.empty() && !(lo.x >= -kUvSlack && lo.y >= -kUvSlack && hi.x <= 1.0 + kUvSlack && hi.y <= 1.0 + kUvSlack)) {
    char range[160];
    std::snprintf(range, sizeof range, "(%.3g, %.3g) to (%.3g, %.3g)", lo.x, lo.y, hi.x, hi.y);
    return fail(label + ": " + name + " runs from " + range +
                ", outside [0, 1]; an AO map needs every triangle inside the texture (tiling UVs cannot hold AO): "
                "bake per vertex instead");
  }
  for (std::size_t v = 0; v < uv.size(); ++v) {
    uv[v] = glm::clamp(glm::vec2(static_cast<float>((*values)[2 * v]), static_cast<float>((*values)[2 * v + 1])),
                       glm::vec2(0.0f), glm::vec2(1.0f));
  }
  return uv;
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

// Step 1 of a texture bake: every part's UVs (read once per primitive) and one map per material.
Result<void> assign_maps(const tinygltf::Model& model, const ModelWalk& walk, const BakeOptions& options,
                         BakeResult& result) {
  std::map<int, std::vector<glm::vec2>> uvs;
  std::map<int, int> map_of_material;
  result.part_map.assign(walk.parts.size(), -1);
  result.part_uv.resize(walk.parts.size());
  for (std::size_t p = 0; p < walk.parts.size(); ++p) {
    const MeshPrimitive& prim = walk.primitives[static_cast<std::size_t>(walk.parts[p].primitive)];
    auto found = uvs.find(walk.parts[p].primitive);
    if (found == uvs.end()) {
      auto read = read_uvs(model, prim, options.uv_set);
      if (!read) return std::unexpected(read.error());
      found = uvs.emplace(walk.parts[p].primitive, std::move(*read)).first;
    }
    result.part_uv[p] = found->second;
    auto [it, added] = map_of_material.try_emplace(prim.material, static_cast<int>(result.maps.size()));
    if (added) {
      AoMap map;
      map.material = prim.material;
      map.size = options.texture_size;
      result.maps.push_back(std::move(map));
    }
    result.part_map[p] = it->second;
  }
  if (result.maps.size() > 1) {
    for (AoMap& map : result.maps) map.label = map.material >= 0 ? "m" + std::to_string(map.material) : "default";
  }
  return {};
}

// Step 2: the receiver normal at every triangle corner of every part, in part order:
// crease-aware geometric ones, or the file's where it has them.
Result<std::vector<glm::vec3>> corner_receiver_normals(const tinygltf::Model& model, const ModelWalk& walk,
                                                       const BakeOptions& options, BakeResult& result) {
  std::vector<glm::vec3> corner_positions;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> corner_source;  // part, vertex
  for (std::size_t p = 0; p < walk.parts.size(); ++p) {
    for (const std::uint32_t v : part_corners(walk, p)) {
      corner_positions.push_back(walk.parts[p].world[v]);
      corner_source.emplace_back(static_cast<std::uint32_t>(p), v);
    }
  }
  std::vector<glm::vec3> normals = corner_normals(corner_positions, kCreaseDegrees);
  if (options.normals != NormalSource::File) return normals;
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
  return normals;
}

// Step 3: the texel receivers, map by map, appended to result.receivers with their map and
// texel. Returns each map's coverage (the receivers themselves moved out).
std::vector<TexelReceivers> place_texel_receivers(const ModelWalk& walk, std::span<const glm::vec3> normals,
                                                  const BakeOptions& options, BakeResult& result) {
  const int size = options.texture_size;
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
          tri.uv[j] = glm::dvec2(result.part_uv[p][corners[t + j]]) * static_cast<double>(size);
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
  return texels;
}

// Step 5: each texel the mean of its receivers, then the margin; overlapping UVs noted.
void fill_maps(const tinygltf::Model& model, const ModelWalk& walk, std::span<const TexelReceivers> texels,
               const BakeOptions& options, BakeResult& result) {
  const int size = options.texture_size;
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
}

// Step 6: the maps into the model: one image, texture and sampler each (the image's bytes come
// at save), and each material's occlusionTexture.
void attach_maps(tinygltf::Model& model, const std::string& name, const ModelWalk& walk, const BakeOptions& options,
                 BakeResult& result) {
  tinygltf::Sampler sampler;
  sampler.name = "exao AO";
  sampler.magFilter = TINYGLTF_TEXTURE_FILTER_LINEAR;
  sampler.minFilter = TINYGLTF_TEXTURE_FILTER_LINEAR_MIPMAP_LINEAR;
  sampler.wrapS = sampler.wrapT = TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE;
  model.samplers.push_back(sampler);
  const int sampler_index = static_cast<int>(model.samplers.size() - 1);
  for (AoMap& map : result.maps) {
    tinygltf::Image image;
    image.name = name + " AO" + (map.label.empty() ? "" : " " + map.label);
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
    tinygltf::Material& target = model.materials[static_cast<std::size_t>(material)];
    if (target.occlusionTexture.index >= 0) {
      result.notes.push_back("material " + (target.name.empty() ? std::to_string(material) : "'" + target.name + "'") +
                             " had an occlusionTexture: the baked map replaces it");
    }
    target.occlusionTexture.index = texture_index;
    target.occlusionTexture.texCoord = options.uv_set;
    target.occlusionTexture.strength = 1.0;
  }
}

Result<BakeResult> bake_texture(Document& document, const BakeOptions& options, const engine::Engine& engine,
                                const ProgressCallback& progress) {
  Document::Impl& doc = document.impl();
  const ModelWalk& walk = doc.walk;
  BakeResult result;
  result.target = Target::Texture;
  if (auto ok = assign_maps(doc.model, walk, options, result); !ok) return std::unexpected(ok.error());
  Result<std::vector<glm::vec3>> normals = corner_receiver_normals(doc.model, walk, options, result);
  if (!normals) return std::unexpected(normals.error());
  const std::vector<TexelReceivers> texels = place_texel_receivers(walk, *normals, options, result);
  if (auto ok = compute(result, engine, progress); !ok) return std::unexpected(ok.error());
  fill_maps(doc.model, walk, texels, options, result);
  attach_maps(doc.model, doc.name, walk, options, result);
  return result;
}

}  // namespace

Result<BakeResult> bake(Document& document, const BakeOptions& options, const engine::Engine& engine,
                        const ProgressCallback& progress) {
  if (auto ok = check_options(options); !ok) return std::unexpected(ok.error());
  Result<BakeResult> result = options.target == Target::Vertex ? bake_vertices(document, options, engine, progress)
                                                               : bake_texture(document, options, engine, progress);
  // What fails past the options is about the input: the message names it.
  if (!result) return fail((document.from_gltf() ? document.impl().source_path : document.name()) + ": " + result.error().message);
  return result;
}

}  // namespace exao::bake
