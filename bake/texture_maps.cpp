// Texture bake steps 2 and 7 (bake/texture_steps.h): which map each part goes to, and each map's
// texels from its receivers' AO, with the margin and the notes.

#include <map>
#include <string>

#include "bake/dilate.h"
#include "bake/labels.h"
#include "bake/texture_steps.h"

namespace exao::bake {
namespace {

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

}  // namespace

void assign_maps(const ModelWalk& walk, const BakeOptions& options, TexturePlan& plan, BakeResult& result) {
  // One map per material, and a separate one for a material's primitives with generated UVs
  // (they get a copy of the material, since one occlusionTexture reads one set).
  const int size = options.texture_size;
  const std::vector<PrimitiveUv>& prim_uv = plan.primitives;
  std::map<std::pair<int, bool>, int>& map_of_key = plan.map_of_key;
  std::vector<bool>& map_generated = plan.map_generated;
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
      // Appended piece by piece: GCC 12 warns falsely (-Wrestrict) on `"m" + std::to_string(...)` here.
      map.label = map.material >= 0 ? std::string("m").append(std::to_string(map.material)) : std::string("default");
      if (map_generated[m]) map.label += "-uv";
    }
  }
}

void fill_maps(const tinygltf::Model& model, const ModelWalk& walk, const BakeOptions& options, const TexturePlan& plan,
               BakeResult& result) {
  const int size = options.texture_size;
  const std::vector<TexelReceivers>& texels = plan.texels;
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
}

}  // namespace exao::bake
