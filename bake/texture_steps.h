#pragma once
// The texture bake, step by step (bake/bake.cpp runs them in this order; each step has a file of
// its own, named after it):
//   1. choose_uvs          (texture_uvs.cpp)    where each primitive's AO UVs come from (uv = ...)
//   2. assign_maps         (texture_maps.cpp)   one map per material, and one more for generated UVs
//   3. generate_atlases    (texture_atlas.cpp)  a box-projection chart atlas per map on generated UVs
//   4. note_uv_choices     (texture_uvs.cpp)    the decisions, one line per mesh
//   5. part_uvs            (texture_uvs.cpp)    per part, the UVs per vertex and per corner
//   6. texel_receivers_of  (texture_texels.cpp) receiver normals per corner, texel receivers per map
//   -- the engine computes the receivers' AO --
//   7. fill_maps           (texture_maps.cpp)   each texel the mean of its receivers, the margin, notes
//   8. write_maps          (texture_output.cpp) the maps, and the generated UV sets, into the model
// Internal to exao_bake (tinygltf).

#include <tiny_gltf.h>

#include <cstdint>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "bake/model_walk.h"
#include "bake/options.h"
#include "bake/result.h"
#include "bake/texel_receivers.h"
#include "bake/uv_choice.h"
#include "core/error.h"

namespace exao::bake {

/// Where one primitive's AO UVs come from (--uv): the file's set, seen through the transform of
/// the texture slot the AO shares, or a generated chart atlas. Decided once per primitive.
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

/// What the steps pass on to each other besides the BakeResult.
struct TexturePlan {
  std::vector<PrimitiveUv> primitives;         // per walk.primitives
  std::vector<int> first_part;                 // per walk.primitives: the first part drawing it, or -1
  std::map<std::pair<int, bool>, int> map_of_key;  // (material, generated UVs) -> map
  std::vector<bool> map_generated;             // per map: on generated UVs
  std::vector<std::string> atlas_figures;      // per map on generated UVs: its atlas, for the notes
  std::vector<TexelReceivers> texels;          // per map (receivers moved into the result)
};

/// Step 1: decides every used primitive's UVs. Fails with uv = file on a primitive without the
/// set or with UVs outside [0, 1].
[[nodiscard]] Result<void> choose_uvs(const tinygltf::Model& model, const ModelWalk& walk, const BakeOptions& options,
                                      TexturePlan& plan);
/// Step 2: result.maps and result.part_map, one map per (material, generated UVs).
void assign_maps(const ModelWalk& walk, const BakeOptions& options, TexturePlan& plan, BakeResult& result);
/// Step 3: the atlas of every map on generated UVs, into the plan's primitives.
[[nodiscard]] Result<void> generate_atlases(const tinygltf::Model& model, const ModelWalk& walk,
                                            const BakeOptions& options, TexturePlan& plan, BakeResult& result);
/// Step 4: the UV decisions into result.notes, one line per mesh.
void note_uv_choices(const tinygltf::Model& model, const ModelWalk& walk, const TexturePlan& plan, BakeResult& result);
/// Step 5: result.part_uv and result.part_corner_uv.
void part_uvs(const ModelWalk& walk, const TexturePlan& plan, BakeResult& result);
/// Step 6: the texel receivers of every map, appended to result.receivers (with their map and texel).
[[nodiscard]] Result<void> texel_receivers_of(const tinygltf::Model& model, const ModelWalk& walk,
                                              const BakeOptions& options, TexturePlan& plan, BakeResult& result);
/// Step 7: each map's texels from result.ao, the dilation margin, and the notes on empty and
/// overlapping maps.
void fill_maps(const tinygltf::Model& model, const ModelWalk& walk, const BakeOptions& options, const TexturePlan& plan,
               BakeResult& result);
/// Step 8: one image, texture and sampler per map, each material's occlusionTexture, and the
/// generated UV sets; `name` names the images.
[[nodiscard]] Result<void> write_maps(tinygltf::Model& model, const std::string& name, const ModelWalk& walk,
                                      const BakeOptions& options, const TexturePlan& plan, BakeResult& result);

}  // namespace exao::bake
