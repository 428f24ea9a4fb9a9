// glTF 2.0 (.gltf/.glb) reader: walks the default scene's node tree and emits world-space
// triangles, one copy per node (and per EXT_mesh_gpu_instancing row) that uses a mesh.
//
// tinygltf parses the JSON and loads the buffers, but it does not check that an accessor's
// bytes lie inside its buffer, nor that indices refer to existing vertices or nodes. Every
// such check is done here before any byte is read: a malformed file yields an error, never a
// read out of bounds.

#include <tiny_gltf.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/constants.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "core/load_scene.h"

namespace exao {
namespace {

constexpr int kByte = TINYGLTF_COMPONENT_TYPE_BYTE;
constexpr int kUnsignedByte = TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE;
constexpr int kShort = TINYGLTF_COMPONENT_TYPE_SHORT;
constexpr int kUnsignedShort = TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT;
constexpr int kUnsignedInt = TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
constexpr int kFloat = TINYGLTF_COMPONENT_TYPE_FLOAT;

// Component types each use may have (glTF 2.0 section 3.7.2.1 and KHR_mesh_quantization).
constexpr std::array kIndexTypes{kUnsignedByte, kUnsignedShort, kUnsignedInt};
constexpr std::array kPositionTypes{kFloat, kByte, kUnsignedByte, kShort, kUnsignedShort};
constexpr std::array kFloatOnly{kFloat};
constexpr std::array kRotationTypes{kFloat, kByte, kShort};

// An accessor without a buffer view (zeros plus sparse values) has no bytes to bound its
// count; this caps what a malformed file can make us allocate. 2^24 elements (16.7 million
// vertices, 400 MB decoded as VEC3 doubles) is far beyond any real sparse-only accessor.
constexpr std::size_t kMaxViewlessCount = std::size_t{1} << 24;

// Joins tinygltf's multi-line messages into one short line.
std::string one_line(std::string_view text) {
  std::string out;
  for (const char c : text) {
    if (c == '\n' || c == '\r') {
      if (!out.empty() && out.back() != ' ') out += "; ";
    } else {
      out += c;
    }
  }
  while (!out.empty() && (out.back() == ' ' || out.back() == ';')) out.pop_back();
  constexpr std::size_t kMaxLength = 200;
  if (out.size() > kMaxLength) out = out.substr(0, kMaxLength) + "...";
  return out.empty() ? "unreadable glTF" : out;
}

int component_size(int component_type) {
  switch (component_type) {
    case kByte:
    case kUnsignedByte:
      return 1;
    case kShort:
    case kUnsignedShort:
      return 2;
    case kUnsignedInt:
    case kFloat:
      return 4;
    default:
      return 0;
  }
}

// One component, decoded as glTF says: normalized integers map to [0, 1] or [-1, 1]
// (glTF 2.0 section 3.11, "max(c / 127, -1)" and so on); others convert as is.
double read_component(const unsigned char* p, int component_type, bool normalized) {
  switch (component_type) {
    case kByte: {
      std::int8_t v;
      std::memcpy(&v, p, sizeof v);
      return normalized ? std::max(v / 127.0, -1.0) : v;
    }
    case kUnsignedByte: {
      std::uint8_t v;
      std::memcpy(&v, p, sizeof v);
      return normalized ? v / 255.0 : v;
    }
    case kShort: {
      std::int16_t v;
      std::memcpy(&v, p, sizeof v);
      return normalized ? std::max(v / 32767.0, -1.0) : v;
    }
    case kUnsignedShort: {
      std::uint16_t v;
      std::memcpy(&v, p, sizeof v);
      return normalized ? v / 65535.0 : v;
    }
    case kUnsignedInt: {
      std::uint32_t v;
      std::memcpy(&v, p, sizeof v);
      return normalized ? v / 4294967295.0 : v;
    }
    default: {  // kFloat: the caller allows no other type
      float v;
      std::memcpy(&v, p, sizeof v);
      return v;
    }
  }
}

// Whether `count` elements of `element` bytes, `stride` apart, starting at `offset`, fit in
// `length` bytes; written so that no intermediate value can overflow.
bool fits(std::size_t offset, std::size_t count, std::size_t stride, std::size_t element,
          std::size_t length) {
  if (count == 0) return offset <= length;
  if (element > length || offset > length - element) return false;
  return stride == 0 || count - 1 <= (length - element - offset) / stride;
}

// The first byte of `count` elements inside buffer view `view_index`, after checking that
// they lie inside the view and the view inside its buffer.
Result<const unsigned char*> view_bytes(const tinygltf::Model& model, int view_index,
                                        std::size_t offset, std::size_t count, std::size_t stride,
                                        std::size_t element, const std::string& what) {
  if (view_index < 0 || static_cast<std::size_t>(view_index) >= model.bufferViews.size()) {
    return fail(what + " refers to buffer view " + std::to_string(view_index) + ", file has " +
                std::to_string(model.bufferViews.size()));
  }
  const tinygltf::BufferView& view = model.bufferViews[static_cast<std::size_t>(view_index)];
  if (view.buffer < 0 || static_cast<std::size_t>(view.buffer) >= model.buffers.size()) {
    return fail("buffer view " + std::to_string(view_index) + " refers to buffer " +
                std::to_string(view.buffer) + ", file has " + std::to_string(model.buffers.size()));
  }
  const std::vector<unsigned char>& data =
      model.buffers[static_cast<std::size_t>(view.buffer)].data;
  if (!fits(view.byteOffset, 1, 0, view.byteLength, data.size())) {
    return fail("buffer view " + std::to_string(view_index) + " (bytes " +
                std::to_string(view.byteOffset) + "+" + std::to_string(view.byteLength) +
                ") exceeds buffer " + std::to_string(view.buffer) + " (" +
                std::to_string(data.size()) + " bytes)");
  }
  if (!fits(offset, count, stride, element, view.byteLength)) {
    return fail(what + " (" + std::to_string(count) + " elements from byte " +
                std::to_string(offset) + ") exceeds its buffer view " + std::to_string(view_index) +
                " (" + std::to_string(view.byteLength) + " bytes)");
  }
  return data.data() + view.byteOffset + offset;
}

// Reads accessor `index` as `count * components` numbers, decoded per read_component, with
// byteStride honoured and any sparse substitution applied. `allowed` lists the component
// types this use accepts; anything else is an error, as is a type of another width, or
// `normalized` where the use forbids it (indices).
Result<std::vector<double>> read_accessor(const tinygltf::Model& model, int index, int components,
                                          std::span<const int> allowed, bool may_normalize,
                                          const std::string& what) {
  if (index < 0 || static_cast<std::size_t>(index) >= model.accessors.size()) {
    return fail(what + " refers to accessor " + std::to_string(index) + ", file has " +
                std::to_string(model.accessors.size()));
  }
  const tinygltf::Accessor& acc = model.accessors[static_cast<std::size_t>(index)];
  const std::string name = "accessor " + std::to_string(index) + " (" + what + ")";
  if (tinygltf::GetNumComponentsInType(static_cast<std::uint32_t>(acc.type)) != components) {
    return fail(
        name + " has " +
        std::to_string(tinygltf::GetNumComponentsInType(static_cast<std::uint32_t>(acc.type))) +
        " components, expected " + std::to_string(components));
  }
  if (std::find(allowed.begin(), allowed.end(), acc.componentType) == allowed.end()) {
    return fail(name + " has unsupported component type " + std::to_string(acc.componentType));
  }
  if (acc.normalized && !may_normalize) return fail(name + " must not be normalized");
  const auto n = static_cast<std::size_t>(components);
  const auto size = static_cast<std::size_t>(component_size(acc.componentType));
  const std::size_t element = n * size;
  if (acc.bufferView < 0 && acc.count > kMaxViewlessCount) {
    return fail(name + " has " + std::to_string(acc.count) + " elements and no buffer view");
  }

  // The bytes are checked before anything is allocated, so a hostile count fails here.
  const unsigned char* base = nullptr;
  std::size_t stride = element;
  if (acc.bufferView >= 0) {
    if (static_cast<std::size_t>(acc.bufferView) < model.bufferViews.size()) {
      const std::size_t given =
          model.bufferViews[static_cast<std::size_t>(acc.bufferView)].byteStride;
      if (given != 0) stride = given;
    }
    if (stride < element) {
      return fail(name + ": byteStride " + std::to_string(stride) + " is less than an element (" +
                  std::to_string(element) + " bytes)");
    }
    auto bytes =
        view_bytes(model, acc.bufferView, acc.byteOffset, acc.count, stride, element, name);
    if (!bytes) return std::unexpected(bytes.error());
    base = *bytes;
  }

  // Without a buffer view the base values are zeros (glTF 2.0 section 3.6.2.3).
  std::vector<double> values(acc.count * n, 0.0);
  if (base != nullptr) {
    for (std::size_t i = 0; i < acc.count; ++i) {
      const unsigned char* p = base + i * stride;
      for (std::size_t c = 0; c < n; ++c) {
        values[i * n + c] = read_component(p + c * size, acc.componentType, acc.normalized);
      }
    }
  }

  if (acc.sparse.isSparse) {
    const int count = acc.sparse.count;
    const int index_type = acc.sparse.indices.componentType;
    if (count < 0 || static_cast<std::size_t>(count) > acc.count) {
      return fail(name + ": sparse count " + std::to_string(count) + " exceeds count " +
                  std::to_string(acc.count));
    }
    if (std::find(kIndexTypes.begin(), kIndexTypes.end(), index_type) == kIndexTypes.end()) {
      return fail(name + ": sparse indices have unsupported component type " +
                  std::to_string(index_type));
    }
    if (acc.sparse.indices.byteOffset < 0 || acc.sparse.values.byteOffset < 0) {
      return fail(name + ": negative sparse byteOffset");
    }
    const auto sparse_count = static_cast<std::size_t>(count);
    const auto index_size = static_cast<std::size_t>(component_size(index_type));
    // Sparse indices and values are tightly packed (glTF 2.0 section 5.1.3).
    auto index_bytes = view_bytes(model, acc.sparse.indices.bufferView,
                                  static_cast<std::size_t>(acc.sparse.indices.byteOffset),
                                  sparse_count, index_size, index_size, name + " sparse indices");
    if (!index_bytes) return std::unexpected(index_bytes.error());
    auto value_bytes = view_bytes(model, acc.sparse.values.bufferView,
                                  static_cast<std::size_t>(acc.sparse.values.byteOffset),
                                  sparse_count, element, element, name + " sparse values");
    if (!value_bytes) return std::unexpected(value_bytes.error());
    for (std::size_t i = 0; i < sparse_count; ++i) {
      const auto target = static_cast<std::size_t>(
          read_component(*index_bytes + i * index_size, index_type, false));
      if (target >= acc.count) {
        return fail(name + ": sparse index " + std::to_string(target) + " >= count " +
                    std::to_string(acc.count));
      }
      for (std::size_t c = 0; c < n; ++c) {
        values[target * n + c] = read_component(*value_bytes + i * element + c * size,
                                                acc.componentType, acc.normalized);
      }
    }
  }
  return values;
}

// A node's local transform: its matrix, or T * R * S (glTF 2.0 section 3.5.3).
Result<glm::dmat4> local_transform(const tinygltf::Node& node, int index) {
  const std::string name = "node " + std::to_string(index);
  if (!node.matrix.empty()) {
    if (node.matrix.size() != 16) {
      return fail(name + ": matrix has " + std::to_string(node.matrix.size()) +
                  " numbers, expected 16");
    }
    return glm::make_mat4(node.matrix.data());  // column-major, as glTF stores it
  }
  glm::dmat4 m(1.0);
  if (!node.translation.empty()) {
    if (node.translation.size() != 3) return fail(name + ": translation needs 3 numbers");
    m = glm::translate(m, glm::make_vec3(node.translation.data()));
  }
  if (!node.rotation.empty()) {
    if (node.rotation.size() != 4) return fail(name + ": rotation needs 4 numbers");
    // glTF stores x, y, z, w; glm's constructor takes w first.
    glm::dquat q(node.rotation[3], node.rotation[0], node.rotation[1], node.rotation[2]);
    const double length = glm::length(q);
    if (length > 0.0 && std::isfinite(length)) q /= length;
    m = m * glm::mat4_cast(q);
  }
  if (!node.scale.empty()) {
    if (node.scale.size() != 3) return fail(name + ": scale needs 3 numbers");
    m = glm::scale(m, glm::make_vec3(node.scale.data()));
  }
  return m;
}

// The positions and triangle corners of one primitive, in the mesh's own space, decoded once
// and reused by every node that instances the mesh.
struct DecodedPrimitive {
  std::vector<double> positions;       // xyz per vertex
  std::vector<std::uint32_t> corners;  // three vertex indices per triangle, front face CCW
  bool two_sided = false;
  std::int32_t material = -1;
};

// Points and lines (modes 0-3) are skipped; strips and fans become triangles that keep the
// strip's orientation (glTF 2.0 section 3.7.2.1 gives these vertex orders).
Result<std::vector<DecodedPrimitive>> decode_mesh(const tinygltf::Model& model, int mesh_index,
                                                  LoadReport& report) {
  const tinygltf::Mesh& mesh = model.meshes[static_cast<std::size_t>(mesh_index)];
  std::vector<DecodedPrimitive> out;
  for (std::size_t p = 0; p < mesh.primitives.size(); ++p) {
    const tinygltf::Primitive& prim = mesh.primitives[p];
    const std::string where =
        "mesh " + std::to_string(mesh_index) + " primitive " + std::to_string(p);
    if (prim.mode >= TINYGLTF_MODE_POINTS && prim.mode <= TINYGLTF_MODE_LINE_STRIP) {
      ++report.primitives_skipped;
      continue;
    }
    if (prim.mode != TINYGLTF_MODE_TRIANGLES && prim.mode != TINYGLTF_MODE_TRIANGLE_STRIP &&
        prim.mode != TINYGLTF_MODE_TRIANGLE_FAN) {
      return fail(where + ": unknown mode " + std::to_string(prim.mode));
    }
    const auto position = prim.attributes.find("POSITION");
    if (position == prim.attributes.end()) {
      // The spec lets a primitive omit positions; viewers draw nothing for it.
      report.notes.push_back(where + " has no POSITION: skipped");
      continue;
    }
    // A Draco primitive's accessors have no bytes unless the file also ships a fallback.
    if (prim.extensions.count("KHR_draco_mesh_compression") != 0 && position->second >= 0 &&
        static_cast<std::size_t>(position->second) < model.accessors.size() &&
        model.accessors[static_cast<std::size_t>(position->second)].bufferView < 0) {
      return fail(where + ": Draco-compressed meshes are not supported");
    }

    DecodedPrimitive decoded;
    auto positions =
        read_accessor(model, position->second, 3, kPositionTypes, true, where + " POSITION");
    if (!positions) return std::unexpected(positions.error());
    decoded.positions = std::move(*positions);
    const std::size_t vertex_count = decoded.positions.size() / 3;

    std::vector<std::uint32_t> order;
    if (prim.indices >= 0) {
      auto indices = read_accessor(model, prim.indices, 1, kIndexTypes, false, where + " indices");
      if (!indices) return std::unexpected(indices.error());
      order.reserve(indices->size());
      for (const double i : *indices) {
        if (i >= static_cast<double>(vertex_count)) {
          return fail(where + ": index " + std::to_string(static_cast<std::uint64_t>(i)) +
                      " >= vertex count " + std::to_string(vertex_count));
        }
        order.push_back(static_cast<std::uint32_t>(i));
      }
    } else {
      if (vertex_count > std::numeric_limits<std::uint32_t>::max()) {
        return fail(where + ": too many vertices");
      }
      order.resize(vertex_count);
      for (std::size_t i = 0; i < vertex_count; ++i) order[i] = static_cast<std::uint32_t>(i);
    }

    const std::size_t n = order.size();
    std::vector<std::uint32_t>& c = decoded.corners;
    if (prim.mode == TINYGLTF_MODE_TRIANGLES) {
      if (n % 3 != 0) {
        report.notes.push_back(where + ": " + std::to_string(n % 3) + " trailing vertices ignored");
      }
      c.assign(order.begin(), order.begin() + static_cast<std::ptrdiff_t>(n - n % 3));
    } else if (n >= 3) {
      c.reserve(3 * (n - 2));
      for (std::size_t i = 0; i + 2 < n; ++i) {
        if (prim.mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
          // Every other triangle swaps its last two corners so all keep the first's winding.
          const std::size_t odd = i % 2;
          c.insert(c.end(), {order[i], order[i + 1 + odd], order[i + 2 - odd]});
        } else {
          c.insert(c.end(), {order[i + 1], order[i + 2], order[0]});
        }
      }
    }

    if (prim.material >= 0) {
      if (static_cast<std::size_t>(prim.material) >= model.materials.size()) {
        return fail(where + " refers to material " + std::to_string(prim.material) + ", file has " +
                    std::to_string(model.materials.size()));
      }
      decoded.material = prim.material;
      decoded.two_sided = model.materials[static_cast<std::size_t>(prim.material)].doubleSided;
    }
    // Without a material the glTF default material applies, and it is single-sided.
    out.push_back(std::move(decoded));
  }
  return out;
}

// Per-instance local transforms from EXT_mesh_gpu_instancing, or one identity when the node
// has none. Each row is T * R * S, applied before the node's world matrix.
Result<std::vector<glm::dmat4>> instance_transforms(const tinygltf::Model& model,
                                                    const tinygltf::Node& node, int index) {
  const auto ext = node.extensions.find("EXT_mesh_gpu_instancing");
  if (ext == node.extensions.end()) return std::vector<glm::dmat4>{glm::dmat4(1.0)};
  const std::string where = "node " + std::to_string(index) + " EXT_mesh_gpu_instancing";
  if (!ext->second.IsObject() || !ext->second.Has("attributes") ||
      !ext->second.Get("attributes").IsObject()) {
    return fail(where + " has no attributes");
  }
  const tinygltf::Value& attributes = ext->second.Get("attributes");
  std::array<std::vector<double>, 3> columns;  // translation, rotation, scale
  const std::array<const char*, 3> names{"TRANSLATION", "ROTATION", "SCALE"};
  const std::array<int, 3> widths{3, 4, 3};
  std::size_t count = 0;
  bool any = false;
  for (std::size_t k = 0; k < 3; ++k) {
    if (!attributes.Has(names[k])) continue;
    const tinygltf::Value& v = attributes.Get(names[k]);
    if (!v.IsNumber()) return fail(where + " " + names[k] + " is not an accessor index");
    const std::span<const int> types =
        k == 1 ? std::span<const int>(kRotationTypes) : std::span<const int>(kFloatOnly);
    auto values =
        read_accessor(model, v.GetNumberAsInt(), widths[k], types, true, where + " " + names[k]);
    if (!values) return std::unexpected(values.error());
    const std::size_t rows = values->size() / static_cast<std::size_t>(widths[k]);
    if (any && rows != count) return fail(where + ": attributes have different counts");
    count = rows;
    any = true;
    columns[k] = std::move(*values);
  }
  if (!any) return fail(where + " has no TRANSLATION, ROTATION or SCALE");
  std::vector<glm::dmat4> out(count, glm::dmat4(1.0));
  for (std::size_t i = 0; i < count; ++i) {
    glm::dmat4& m = out[i];
    if (!columns[0].empty()) m = glm::translate(m, glm::make_vec3(&columns[0][3 * i]));
    if (!columns[1].empty()) {
      const double* r = &columns[1][4 * i];
      glm::dquat q(r[3], r[0], r[1], r[2]);
      const double length = glm::length(q);
      if (length > 0.0 && std::isfinite(length)) q /= length;
      m = m * glm::mat4_cast(q);
    }
    if (!columns[2].empty()) m = glm::scale(m, glm::make_vec3(&columns[2][3 * i]));
  }
  return out;
}

// A camera at the node's world pose: glTF cameras look down their local -Z with +Y up.
void add_camera(const tinygltf::Model& model, const tinygltf::Node& node, const glm::dmat4& world,
                Scene& scene) {
  const tinygltf::Camera& cam = model.cameras[static_cast<std::size_t>(node.camera)];
  const std::string name = !cam.name.empty()    ? cam.name
                           : !node.name.empty() ? node.name
                                                : "camera " + std::to_string(node.camera);
  if (cam.type != "perspective") {
    scene.report.notes.push_back("camera '" + name + "' is " + cam.type +
                                 ": skipped (perspective only)");
    return;
  }
  const glm::dmat3 basis(world);
  const glm::dvec3 forward = basis * glm::dvec3(0.0, 0.0, -1.0);
  const glm::dvec3 up_raw = basis * glm::dvec3(0.0, 1.0, 0.0);
  const double forward_length = glm::length(forward);
  // Gram-Schmidt: the node's matrix may carry scale or shear.
  const glm::dvec3 f = forward / forward_length;
  const glm::dvec3 u_raw = up_raw - glm::dot(up_raw, f) * f;
  const double up_length = glm::length(u_raw);
  const double yfov = cam.perspective.yfov;
  const glm::dvec3 eye(world[3]);
  const bool finite = std::isfinite(forward_length) && std::isfinite(up_length) &&
                      std::isfinite(eye.x) && std::isfinite(eye.y) && std::isfinite(eye.z);
  if (!finite || forward_length <= 0.0 || up_length <= 1e-12 * forward_length) {
    scene.report.notes.push_back("camera '" + name + "' has a degenerate transform: skipped");
    return;
  }
  if (!(yfov > 0.0 && yfov < glm::pi<double>())) {
    scene.report.notes.push_back("camera '" + name + "' has yfov " + std::to_string(yfov) +
                                 ": skipped");
    return;
  }
  Camera camera;
  camera.name = name;
  camera.eye = glm::vec3(eye);
  camera.forward = glm::vec3(f);
  camera.up = glm::vec3(u_raw / up_length);
  camera.yfov = static_cast<float>(yfov);
  if (cam.perspective.aspectRatio > 0.0) {
    camera.aspect = static_cast<float>(cam.perspective.aspectRatio);
  }
  scene.cameras.push_back(std::move(camera));
}

void emit(const DecodedPrimitive& prim, const glm::dmat4& world, Scene& scene) {
  // A mirroring transform turns counter-clockwise into clockwise; swapping two corners keeps
  // the front face counter-clockwise in world space (glTF 2.0 section 3.7.4).
  const bool mirrored = glm::determinant(world) < 0.0;
  const std::size_t vertex_count = prim.positions.size() / 3;
  std::vector<glm::vec3> world_positions(vertex_count);
  for (std::size_t v = 0; v < vertex_count; ++v) {
    world_positions[v] = glm::vec3(world * glm::dvec4(glm::make_vec3(&prim.positions[3 * v]), 1.0));
  }
  for (std::size_t t = 0; t + 2 < prim.corners.size(); t += 3) {
    const glm::vec3& a = world_positions[prim.corners[t]];
    const glm::vec3& b = world_positions[prim.corners[t + 1]];
    const glm::vec3& c = world_positions[prim.corners[t + 2]];
    if (mirrored) {
      scene.add_triangle(a, c, b, prim.two_sided, prim.material);
    } else {
      scene.add_triangle(a, b, c, prim.two_sided, prim.material);
    }
  }
}

// Extensions that change how geometry is stored; a file that requires one we cannot decode
// would otherwise load as garbage.
Result<void> check_required_extensions(const tinygltf::Model& model) {
  constexpr std::array<std::string_view, 3> kUnsupported{
      "KHR_draco_mesh_compression", "EXT_meshopt_compression", "KHR_meshopt_compression"};
  for (const std::string& ext : model.extensionsRequired) {
    if (std::find(kUnsupported.begin(), kUnsupported.end(), ext) != kUnsupported.end()) {
      return fail("requires " + ext + ", which is not supported");
    }
  }
  return {};
}

// The root nodes to draw: the default scene's, else scene 0's, else every node that is
// nobody's child.
Result<std::vector<int>> root_nodes(const tinygltf::Model& model) {
  if (!model.scenes.empty()) {
    int s = model.defaultScene;
    if (s < 0) s = 0;
    if (static_cast<std::size_t>(s) >= model.scenes.size()) {
      return fail("default scene " + std::to_string(s) + " does not exist (file has " +
                  std::to_string(model.scenes.size()) + ")");
    }
    return model.scenes[static_cast<std::size_t>(s)].nodes;
  }
  std::vector<bool> is_child(model.nodes.size(), false);
  for (const tinygltf::Node& node : model.nodes) {
    for (const int c : node.children) {
      if (c >= 0 && static_cast<std::size_t>(c) < is_child.size()) {
        is_child[static_cast<std::size_t>(c)] = true;
      }
    }
  }
  std::vector<int> roots;
  for (std::size_t i = 0; i < model.nodes.size(); ++i) {
    if (!is_child[i]) roots.push_back(static_cast<int>(i));
  }
  return roots;
}

Result<Scene> build_scene(const tinygltf::Model& model) {
  if (auto ok = check_required_extensions(model); !ok) return std::unexpected(ok.error());
  auto roots = root_nodes(model);
  if (!roots) return std::unexpected(roots.error());

  Scene scene;
  std::map<int, std::vector<DecodedPrimitive>> meshes;  // decoded on first use
  std::size_t skinned = 0;
  // Depth-first, parents before children, children in file order; explicit stack so a deep
  // (or hostile) hierarchy cannot overflow the call stack.
  struct Visit {
    int node;
    glm::dmat4 parent;
  };
  std::vector<Visit> stack;
  for (auto it = roots->rbegin(); it != roots->rend(); ++it) {
    stack.push_back({*it, glm::dmat4(1.0)});
  }
  std::vector<bool> visited(model.nodes.size(), false);
  while (!stack.empty()) {
    const Visit visit = stack.back();
    stack.pop_back();
    if (visit.node < 0 || static_cast<std::size_t>(visit.node) >= model.nodes.size()) {
      return fail("scene refers to node " + std::to_string(visit.node) + ", file has " +
                  std::to_string(model.nodes.size()));
    }
    const auto index = static_cast<std::size_t>(visit.node);
    // glTF node hierarchies are strict trees; a node reached twice means a cycle.
    if (visited[index]) {
      return fail("node " + std::to_string(visit.node) + " is reached twice in the node tree");
    }
    visited[index] = true;
    const tinygltf::Node& node = model.nodes[index];
    auto local = local_transform(node, visit.node);
    if (!local) return std::unexpected(local.error());
    const glm::dmat4 world = visit.parent * *local;

    if (node.camera >= 0) {
      if (static_cast<std::size_t>(node.camera) >= model.cameras.size()) {
        return fail("node " + std::to_string(visit.node) + " refers to camera " +
                    std::to_string(node.camera) + ", file has " +
                    std::to_string(model.cameras.size()));
      }
      add_camera(model, node, world, scene);
    }
    if (node.mesh >= 0) {
      if (static_cast<std::size_t>(node.mesh) >= model.meshes.size()) {
        return fail("node " + std::to_string(visit.node) + " refers to mesh " +
                    std::to_string(node.mesh) + ", file has " +
                    std::to_string(model.meshes.size()));
      }
      auto found = meshes.find(node.mesh);
      if (found == meshes.end()) {
        auto decoded = decode_mesh(model, node.mesh, scene.report);
        if (!decoded) return std::unexpected(decoded.error());
        found = meshes.emplace(node.mesh, std::move(*decoded)).first;
      }
      auto instances = instance_transforms(model, node, visit.node);
      if (!instances) return std::unexpected(instances.error());
      if (node.skin >= 0) ++skinned;
      for (const glm::dmat4& instance : *instances) {
        for (const DecodedPrimitive& prim : found->second) emit(prim, world * instance, scene);
      }
    }
    for (auto it = node.children.rbegin(); it != node.children.rend(); ++it) {
      stack.push_back({*it, world});
    }
  }

  if (scene.report.primitives_skipped > 0) {
    scene.report.notes.push_back(std::to_string(scene.report.primitives_skipped) +
                                 " point/line primitive uses skipped (AO needs triangles)");
  }
  if (skinned > 0) {
    scene.report.notes.push_back(
        std::to_string(skinned) +
        " skinned mesh node(s) drawn in their bind pose (skinning is not applied)");
  }
  if (scene.triangle_count() == 0) return fail("no triangles");
  return scene;
}

// AO needs no texture: images are neither decoded nor required to exist.
bool ignore_image(tinygltf::Image*, const int, std::string*, std::string*, int, int,
                  const unsigned char*, int, void*) {
  return true;
}

bool starts_with_glb_magic(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::array<char, 4> magic{};
  in.read(magic.data(), magic.size());
  return in.gcount() == 4 && std::memcmp(magic.data(), "glTF", 4) == 0;
}

Result<Scene> load(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return fail("no such file");
  tinygltf::TinyGLTF context;
  context.SetImageLoader(&ignore_image, nullptr);
  tinygltf::Model model;
  std::string err;
  std::string warn;
  // The container is told by its magic, not its name, so a mislabelled file still loads.
  const bool binary = starts_with_glb_magic(path);
  const bool ok = binary ? context.LoadBinaryFromFile(&model, &err, &warn, path)
                         : context.LoadASCIIFromFile(&model, &err, &warn, path);
  if (!ok) return fail(one_line(err));
  return build_scene(model);
}

}  // namespace

Result<Scene> load_gltf(const std::string& path) {
  Result<Scene> scene;
  // tinygltf and the standard library may throw (bad_alloc on a hostile count, json errors);
  // no exception leaves the loader.
  try {
    scene = load(path);
  } catch (const std::exception& e) {
    scene = fail(one_line(e.what()));
  } catch (...) {
    scene = fail("unknown error while reading glTF");
  }
  if (!scene) return fail(path + ": " + scene.error().message);
  scene->name = std::filesystem::path(path).stem().string();
  return scene;
}

}  // namespace exao
