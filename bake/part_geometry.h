#pragma once
// A part's triangles and the file's normals, as both bakes read them. Internal to exao_bake.

#include <tiny_gltf.h>

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "bake/model_walk.h"
#include "core/error.h"

namespace exao::bake {

/// Front-face corners of walk.parts[part], three per triangle, as the scene has them.
[[nodiscard]] std::vector<std::uint32_t> part_corners(const ModelWalk& walk, std::size_t part);

/// The file's NORMALs of walk.parts[part] in world space (the inverse transpose of the node's
/// matrix), unit or zero where broken; an empty vector when the primitive has none.
[[nodiscard]] Result<std::vector<glm::vec3>> file_normals(const tinygltf::Model& model, const ModelWalk& walk, std::size_t part);

}  // namespace exao::bake
