#pragma once
// Reading glTF accessors safely and appending new ones: the byte-level access every part of the
// bake shares. Internal to exao_bake (it exposes tinygltf, which the library links privately).
//
// Reading follows core/gltf_loader.cpp: tinygltf does not check that an accessor's bytes lie
// inside its buffer, so every bound is checked here before a byte is read, and a malformed file
// yields an error naming the accessor, never a read out of bounds.

#include <tiny_gltf.h>

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "core/error.h"

namespace exao::bake {

inline constexpr int kByte = TINYGLTF_COMPONENT_TYPE_BYTE;
inline constexpr int kUnsignedByte = TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE;
inline constexpr int kShort = TINYGLTF_COMPONENT_TYPE_SHORT;
inline constexpr int kUnsignedShort = TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT;
inline constexpr int kUnsignedInt = TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
inline constexpr int kFloat = TINYGLTF_COMPONENT_TYPE_FLOAT;

// Component types each use may have (glTF 2.0 section 3.7.2.1 and KHR_mesh_quantization).
inline constexpr std::array kIndexTypes{kUnsignedByte, kUnsignedShort, kUnsignedInt};
inline constexpr std::array kPositionTypes{kFloat, kByte, kUnsignedByte, kShort, kUnsignedShort};
inline constexpr std::array kNormalTypes{kFloat, kByte, kShort};
inline constexpr std::array kTexcoordTypes{kFloat, kByte, kUnsignedByte, kShort, kUnsignedShort};
inline constexpr std::array kColorTypes{kFloat, kUnsignedByte, kUnsignedShort};
inline constexpr std::array kFloatOnly{kFloat};
inline constexpr std::array kRotationTypes{kFloat, kByte, kShort};

/// Accessor `index` as count * components numbers, normalised integers decoded to [0, 1] or
/// [-1, 1] (glTF 2.0 section 3.11), byteStride honoured, sparse values substituted. `allowed`
/// lists the component types this use accepts. `what` names the use in the error.
[[nodiscard]] Result<std::vector<double>> read_accessor(const tinygltf::Model& model, int index, int components,
                                                        std::span<const int> allowed, bool may_normalize,
                                                        const std::string& what);

/// Number of components of an accessor's type (1 for SCALAR ... 16 for MAT4); 0 when unknown.
[[nodiscard]] int accessor_components(const tinygltf::Model& model, int index);

/// Joins tinygltf's multi-line messages into one short line.
[[nodiscard]] std::string one_line(const std::string& text);

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
