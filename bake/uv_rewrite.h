#pragma once
// Writing a generated AO UV set into a glTF primitive (exao bake --uv generate|auto). Charts need
// seams, so vertices on a seam are split: the primitive gets new vertices, each a copy of an old
// one, with every attribute and morph target copied along in its own type, and the new UVs as
// TEXCOORD_<set>. Internal to exao_bake (it exposes tinygltf).

#include <tiny_gltf.h>

#include <cstdint>
#include <span>
#include <string>

#include <glm/glm.hpp>

#include "core/error.h"

namespace exao::bake {

/// Rewrites primitive `primitive` of mesh `mesh`: new vertex i copies old vertex source[i];
/// `corners` (three per triangle, into the new vertices) become its indices, in TRIANGLES mode
/// (strips and fans were already unrolled into corners); `uv` (per new vertex, in [0, 1]^2)
/// becomes TEXCOORD_<set>, and also every lower TEXCOORD_k the primitive lacks, since glTF wants
/// the sets numbered without gaps. Attributes keep their component type and normalisation; views
/// get a 4-byte aligned stride; min / max are recomputed where the input had them. Fails, naming
/// `label`, when an attribute cannot be read or its count differs from POSITION's.
[[nodiscard]] Result<void> write_generated_uvs(tinygltf::Model& model, int mesh, int primitive,
                                               std::span<const std::uint32_t> source, std::span<const glm::vec2> uv,
                                               std::span<const std::uint32_t> corners, int set, const std::string& label);

}  // namespace exao::bake
