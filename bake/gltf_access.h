#pragma once
// Reading glTF accessors safely (io/gltf_model.h, shared with the scene loader) and appending
// new ones: the byte-level access every part of the bake shares. Internal to exao_bake (it
// exposes tinygltf, which the library links privately).

#include <tiny_gltf.h>

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "core/error.h"
#include "io/gltf_model.h"

namespace exao::bake {

// The reading side is io/gltf_model.h, shared with the scene loader.
using gltf::kByte;
using gltf::kColorTypes;
using gltf::kFloat;
using gltf::kFloatOnly;
using gltf::kIndexTypes;
using gltf::kNormalTypes;
using gltf::kPositionTypes;
using gltf::kRotationTypes;
using gltf::kShort;
using gltf::kTexcoordTypes;
using gltf::kUnsignedByte;
using gltf::kUnsignedInt;
using gltf::kUnsignedShort;
using gltf::ModelBytes;
using gltf::one_line;
using gltf::read_accessor;

/// Number of components of an accessor's type (1 for SCALAR ... 16 for MAT4); 0 when unknown.
[[nodiscard]] int accessor_components(const tinygltf::Model& model, int index);

/// Appends `bytes` to the buffer that holds what the bake adds (created on first use, merged
/// with the others when saving) as a new buffer view, 4-byte aligned (glTF 2.0 section 3.6.2.4).
/// `target` is TINYGLTF_TARGET_ARRAY_BUFFER, _ELEMENT_ARRAY_BUFFER, or 0 (images). Returns its index.
int append_buffer_view(tinygltf::Model& model, std::span<const std::uint8_t> bytes, int target);

/// A new float accessor of count = values.size() / components elements (1: SCALAR, 2: VEC2,
/// 3: VEC3, 4: VEC4) in a view of its own, with min and max (required for POSITION, harmless
/// elsewhere). Returns its index.
int append_float_accessor(tinygltf::Model& model, std::span<const float> values, int components);

/// A new UNSIGNED_INT index accessor. Returns its index.
int append_index_accessor(tinygltf::Model& model, std::span<const std::uint32_t> indices);

}  // namespace exao::bake
