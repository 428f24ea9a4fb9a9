#pragma once
// A triangle soup (a built-in scene, or an OBJ/PLY/OFF/STL read by core) as a glTF model, so
// that every input is baked and written the same way. Internal to exao_bake (tinygltf).

#include <tiny_gltf.h>

#include "bake/options.h"
#include "core/error.h"
#include "core/scene.h"

namespace exao::bake {

/// One mesh on one node; a primitive per (material, sidedness) group, with welded vertices
/// (equal positions become one vertex) and UNSIGNED_INT indices; TEXCOORD_0 from box_atlas when
/// convert.atlas_size > 0; a white, non-metallic material per group with doubleSided as the
/// triangles were; the scene's cameras as perspective camera nodes.
[[nodiscard]] Result<tinygltf::Model> scene_to_gltf(const Scene& scene, const ConvertOptions& convert);

}  // namespace exao::bake
