// Texture bake steps 1, 4 and 5 (bake/texture_steps.h): the UV choice per primitive, its notes,
// and the UVs per part.

#include <algorithm>
#include <cstdio>
#include <optional>

#include "bake/gltf_access.h"
#include "bake/labels.h"
#include "bake/texture_steps.h"

namespace exao::bake {
namespace {

// A primitive's UV set `set` per vertex as stored (normalised integers decoded), or nothing when
// the primitive has no such set.
Result<std::optional<std::vector<glm::dvec2>>> read_uv_set(const tinygltf::Model& model, const MeshPrimitive& prim, int set) {
  const std::string name = "TEXCOORD_" + std::to_string(set);
  const tinygltf::Primitive& gp = gltf_primitive(model, prim);
  const auto found = gp.attributes.find(name);
  if (found == gp.attributes.end()) return std::optional<std::vector<glm::dvec2>>{};
  const std::string label = primitive_label(model, prim);
  auto values = read_accessor(ModelBytes(model), found->second, 2, kTexcoordTypes, true, label + " " + name);
  if (!values) return std::unexpected(values.error());
  if (values->size() != 2 * prim.positions.size()) return fail(label + ": " + name + " has a different count than POSITION");
  std::vector<glm::dvec2> uv(prim.positions.size());
  for (std::size_t v = 0; v < uv.size(); ++v) uv[v] = glm::dvec2((*values)[2 * v], (*values)[2 * v + 1]);
  return std::optional<std::vector<glm::dvec2>>(std::move(uv));
}

std::string percent(double share) {
  char text[32];
  std::snprintf(text, sizeof text, share > 0.0 && share < 0.001 ? "%.2f%%" : "%.1f%%", 100.0 * share);
  return text;
}

}  // namespace

Result<void> choose_uvs(const tinygltf::Model& model, const ModelWalk& walk, const BakeOptions& options,
                        TexturePlan& plan) {
  const int size = options.texture_size;
  std::vector<PrimitiveUv>& prim_uv = plan.primitives;
  prim_uv.assign(walk.primitives.size(), {});
  std::vector<int>& first_part = plan.first_part;
  first_part.assign(walk.primitives.size(), -1);
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
  return {};
}

void note_uv_choices(const tinygltf::Model& model, const ModelWalk& walk, const TexturePlan& plan, BakeResult& result) {
  const std::vector<PrimitiveUv>& prim_uv = plan.primitives;
  const std::vector<bool>& map_generated = plan.map_generated;
  const std::vector<std::string>& atlas_figures = plan.atlas_figures;
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

void part_uvs(const ModelWalk& walk, const TexturePlan& plan, BakeResult& result) {
  const std::vector<PrimitiveUv>& prim_uv = plan.primitives;
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
}

}  // namespace exao::bake
