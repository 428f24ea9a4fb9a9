#pragma once
// exao::gltf: reading a tinygltf Model safely, shared by the scene loader (io/gltf_loader.cpp)
// and the bake (bake/), so that both see the same nodes, transforms and accessor values.
// Internal: it exposes tinygltf, which the modules that include it link privately.
//
// tinygltf parses the JSON and loads the buffers, but it does not check that an accessor's
// bytes lie inside its buffer, nor that indices refer to existing nodes. Every such check is
// done here before any byte is read: a malformed file yields an error, never a read out of
// bounds.

#include <tiny_gltf.h>

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>

#include "core/error.h"
#include "core/scene.h"

namespace exao::gltf {

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

/// A model and where its buffers' bytes are: model.buffers[i].data, except a GLB's BIN chunk that
/// the scene loader leaves in the mapped file (io/glb_in_place.h). Every accessor is read through
/// this, so its bounds are checked against the bytes actually read.
struct ModelBytes {
  const tinygltf::Model& model;
  std::span<const unsigned char> buffer0_in_place;  // no data: buffer 0 is model.buffers[0].data

  explicit ModelBytes(const tinygltf::Model& m) : model(m) {}
  ModelBytes(const tinygltf::Model& m, std::span<const unsigned char> in_place) : model(m), buffer0_in_place(in_place) {}
  /// Buffer `i`'s bytes (i < model.buffers.size()).
  [[nodiscard]] std::span<const unsigned char> buffer(std::size_t i) const {
    if (i == 0 && buffer0_in_place.data() != nullptr) return buffer0_in_place;
    return model.buffers[i].data;
  }
};

/// Joins tinygltf's multi-line messages into one short line.
[[nodiscard]] std::string one_line(std::string_view text);

/// Accessor `index` as count * components numbers, normalised integers decoded to [0, 1] or
/// [-1, 1] (glTF 2.0 section 3.11), byteStride honoured, sparse values substituted. `allowed`
/// lists the component types this use accepts; anything else is an error, as is a type of
/// another width, or `normalized` where `may_normalize` is false (indices). `what` names the use.
[[nodiscard]] Result<std::vector<double>> read_accessor(const ModelBytes& source, int index, int components,
                                                        std::span<const int> allowed, bool may_normalize,
                                                        const std::string& what);

/// How the hot accessors (positions, indices) are read. Direct decodes each component type in a
/// loop of its own straight from the buffer; Generic goes through read_accessor's doubles. Both
/// make every check read_accessor makes and give the same values, bit for bit, and the same
/// errors (tests/gltf_direct_test.cpp): Generic is the reference the direct loops are tested
/// against.
enum class AccessorPath { Direct, Generic };

/// A VEC3 accessor (POSITION) as read_accessor decodes it, one dvec3 per element.
[[nodiscard]] Result<std::vector<glm::dvec3>> read_vec3(const ModelBytes& source, int index,
                                                        std::span<const int> allowed, bool may_normalize,
                                                        const std::string& what,
                                                        AccessorPath path = AccessorPath::Direct);

/// A primitive's index accessor (unsigned byte, short or int; never normalized), each index
/// checked against `vertex_count`: fails with "WHERE: index I >= vertex count N" at the first one
/// out of range. `where` names the primitive ("mesh 0 primitive 1").
[[nodiscard]] Result<std::vector<std::uint32_t>> read_indices(const ModelBytes& source, int index,
                                                              std::size_t vertex_count, const std::string& where,
                                                              AccessorPath path = AccessorPath::Direct);

/// A node's local transform: its matrix, or T * R * S (glTF 2.0 section 3.5.3).
[[nodiscard]] Result<glm::dmat4> local_transform(const tinygltf::Node& node, int index);

/// Per-instance local transforms from EXT_mesh_gpu_instancing, or one identity when the node
/// has none. Each row is T * R * S, applied before the node's world matrix.
[[nodiscard]] Result<std::vector<glm::dmat4>> instance_transforms(const ModelBytes& source,
                                                                  const tinygltf::Node& node, int index);

/// Adds the node's perspective camera at its world pose to scene.cameras (glTF cameras look down
/// their local -Z with +Y up); other cameras and degenerate poses are skipped with a note.
void add_camera(const tinygltf::Model& model, const tinygltf::Node& node, const glm::dmat4& world, Scene& scene);

/// Fails when the file requires an extension that changes how geometry is stored and that exao
/// cannot decode (Draco, meshopt): it would otherwise load as garbage.
[[nodiscard]] Result<void> check_required_extensions(const tinygltf::Model& model);

/// The root nodes to draw: the default scene's, else scene 0's, else every node that is nobody's
/// child.
[[nodiscard]] Result<std::vector<int>> root_nodes(const tinygltf::Model& model);

}  // namespace exao::gltf
