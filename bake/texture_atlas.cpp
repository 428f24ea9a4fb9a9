// Texture bake step 3 (bake/texture_steps.h): generated UVs, one box-projection chart atlas per
// map (bake/box_atlas.h), split into each primitive's new vertices.

#include <algorithm>
#include <cstdio>
#include <exception>
#include <map>

#include "bake/box_atlas.h"
#include "bake/labels.h"
#include "bake/texture_steps.h"

namespace exao::bake {
namespace {

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

}  // namespace

Result<void> generate_atlases(const tinygltf::Model& model, const ModelWalk& walk, const BakeOptions& options,
                              TexturePlan& plan, BakeResult& result) {
  // Generated UVs: one box-projection chart atlas per map, over the world-space triangles (as
  // the first node that draws each primitive places them), so texel density is even across it.
  const int size = options.texture_size;
  std::vector<PrimitiveUv>& prim_uv = plan.primitives;
  const std::vector<int>& first_part = plan.first_part;
  const std::vector<bool>& map_generated = plan.map_generated;
  std::vector<std::string>& atlas_figures = plan.atlas_figures;
  atlas_figures.assign(result.maps.size(), {});
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
  return {};
}

}  // namespace exao::bake
