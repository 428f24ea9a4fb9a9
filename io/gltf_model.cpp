#include "io/gltf_model.h"


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
#include <type_traits>
#include <utility>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/constants.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "core/huge_pages.h"

namespace exao::gltf {
namespace {

// An accessor without a buffer view (zeros plus sparse values) has no bytes to bound its
// count; this caps what a malformed file can make us allocate. 2^24 elements (16.7 million
// vertices, 400 MB decoded as VEC3 doubles) is far beyond any real sparse-only accessor.
constexpr std::size_t kMaxViewlessCount = std::size_t{1} << 24;

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

// One integer component of type T at p; normalized, it maps to [0, 1] (unsigned) or [-1, 1]
// (signed: glTF 2.0 section 3.11, "max(c / 127, -1)" and so on), else converts as is.
template <class T>
double integer_component(const unsigned char* p, bool normalized) {
  T v;
  std::memcpy(&v, p, sizeof v);
  if (!normalized) return v;
  constexpr double kTop = std::numeric_limits<T>::max();
  return std::is_signed_v<T> ? std::max(v / kTop, -1.0) : v / kTop;
}

// One component, decoded as glTF says (integer_component); floats convert as is.
double read_component(const unsigned char* p, int component_type, bool normalized) {
  switch (component_type) {
    case kByte: return integer_component<std::int8_t>(p, normalized);
    case kUnsignedByte: return integer_component<std::uint8_t>(p, normalized);
    case kShort: return integer_component<std::int16_t>(p, normalized);
    case kUnsignedShort: return integer_component<std::uint16_t>(p, normalized);
    case kUnsignedInt: return integer_component<std::uint32_t>(p, normalized);
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
Result<const unsigned char*> view_bytes(const ModelBytes& source, int view_index,
                                        std::size_t offset, std::size_t count, std::size_t stride,
                                        std::size_t element, const std::string& what) {
  const tinygltf::Model& model = source.model;
  if (view_index < 0 || static_cast<std::size_t>(view_index) >= model.bufferViews.size()) {
    return fail(what + " refers to buffer view " + std::to_string(view_index) + ", file has " +
                std::to_string(model.bufferViews.size()));
  }
  const tinygltf::BufferView& view = model.bufferViews[static_cast<std::size_t>(view_index)];
  if (view.buffer < 0 || static_cast<std::size_t>(view.buffer) >= model.buffers.size()) {
    return fail("buffer view " + std::to_string(view_index) + " refers to buffer " +
                std::to_string(view.buffer) + ", file has " + std::to_string(model.buffers.size()));
  }
  const std::span<const unsigned char> data = source.buffer(static_cast<std::size_t>(view.buffer));
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

}  // namespace

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

namespace {

// An accessor's bytes, every check of read_accessor passed: `count` elements of `element` bytes,
// `stride` apart from `base` (nullptr: no buffer view, zeros), and where its sparse
// substitution lies.
struct AccessorBytes {
  const tinygltf::Accessor* accessor = nullptr;
  const unsigned char* base = nullptr;
  std::size_t count = 0;
  std::size_t stride = 0;
  std::size_t element = 0;
  std::size_t component = 0;                 // bytes of one component
  std::size_t sparse_count = 0;              // 0 without sparse values
  const unsigned char* sparse_indices = nullptr;
  const unsigned char* sparse_values = nullptr;
  int sparse_index_type = 0;
  std::string name;                          // "accessor N (what)", for errors
};

// Every check read_accessor makes, before a value is read or an element allocated.
Result<AccessorBytes> locate_accessor(const ModelBytes& source, int index, int components,
                                      std::span<const int> allowed, bool may_normalize, const std::string& what) {
  const tinygltf::Model& model = source.model;
  if (index < 0 || static_cast<std::size_t>(index) >= model.accessors.size()) {
    return fail(what + " refers to accessor " + std::to_string(index) + ", file has " +
                std::to_string(model.accessors.size()));
  }
  const tinygltf::Accessor& acc = model.accessors[static_cast<std::size_t>(index)];
  AccessorBytes out;
  out.accessor = &acc;
  out.name = "accessor " + std::to_string(index) + " (" + what + ")";
  const std::string& name = out.name;
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
  out.component = static_cast<std::size_t>(component_size(acc.componentType));
  out.element = n * out.component;
  out.count = acc.count;
  out.stride = out.element;
  if (acc.bufferView < 0 && acc.count > kMaxViewlessCount) {
    return fail(name + " has " + std::to_string(acc.count) + " elements and no buffer view");
  }

  // The bytes are checked before anything is allocated, so a hostile count fails here.
  if (acc.bufferView >= 0) {
    if (static_cast<std::size_t>(acc.bufferView) < model.bufferViews.size()) {
      const std::size_t given =
          model.bufferViews[static_cast<std::size_t>(acc.bufferView)].byteStride;
      if (given != 0) out.stride = given;
    }
    if (out.stride < out.element) {
      return fail(name + ": byteStride " + std::to_string(out.stride) + " is less than an element (" +
                  std::to_string(out.element) + " bytes)");
    }
    auto bytes =
        view_bytes(source, acc.bufferView, acc.byteOffset, acc.count, out.stride, out.element, name);
    if (!bytes) return std::unexpected(bytes.error());
    out.base = *bytes;
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
    auto index_bytes = view_bytes(source, acc.sparse.indices.bufferView,
                                  static_cast<std::size_t>(acc.sparse.indices.byteOffset),
                                  sparse_count, index_size, index_size, name + " sparse indices");
    if (!index_bytes) return std::unexpected(index_bytes.error());
    auto value_bytes = view_bytes(source, acc.sparse.values.bufferView,
                                  static_cast<std::size_t>(acc.sparse.values.byteOffset),
                                  sparse_count, out.element, out.element, name + " sparse values");
    if (!value_bytes) return std::unexpected(value_bytes.error());
    out.sparse_count = sparse_count;
    out.sparse_index_type = index_type;
    out.sparse_indices = *index_bytes;
    out.sparse_values = *value_bytes;
  }
  return out;
}

// The sparse substitution (glTF 2.0 section 3.6.2.3): set(target, value bytes) for each sparse
// entry in file order, after checking its target index; a later entry overwrites an earlier one.
template <class Set>
Result<void> substitute_sparse(const AccessorBytes& a, Set&& set) {
  const auto index_size = static_cast<std::size_t>(component_size(a.sparse_index_type));
  for (std::size_t i = 0; i < a.sparse_count; ++i) {
    const auto target =
        static_cast<std::size_t>(read_component(a.sparse_indices + i * index_size, a.sparse_index_type, false));
    if (target >= a.count) {
      return fail(a.name + ": sparse index " + std::to_string(target) + " >= count " + std::to_string(a.count));
    }
    set(target, a.sparse_values + i * a.element);
  }
  return {};
}

// The elements of a VEC3 accessor as read_component decodes them; float components (the common
// case) are read without the per-component type switch.
void decode_vec3(const AccessorBytes& a, std::span<glm::dvec3> out) {
  const int type = a.accessor->componentType;
  const bool normalized = a.accessor->normalized;
  if (type == kFloat) {
    for (std::size_t i = 0; i < a.count; ++i) {
      float v[3];
      std::memcpy(v, a.base + i * a.stride, sizeof v);
      out[i] = glm::dvec3(v[0], v[1], v[2]);
    }
    return;
  }
  for (std::size_t i = 0; i < a.count; ++i) {
    const unsigned char* p = a.base + i * a.stride;
    out[i] = glm::dvec3(read_component(p, type, normalized), read_component(p + a.component, type, normalized),
                        read_component(p + 2 * a.component, type, normalized));
  }
}

// Indices of type T, each checked against the vertex count, in file order.
template <class T>
Result<void> decode_indices(const AccessorBytes& a, std::size_t vertex_count, const std::string& where,
                            std::uint32_t* out) {
  for (std::size_t i = 0; i < a.count; ++i) {
    T v;
    std::memcpy(&v, a.base + i * a.stride, sizeof v);
    if (v >= vertex_count) {
      return fail(where + ": index " + std::to_string(static_cast<std::uint64_t>(v)) + " >= vertex count " +
                  std::to_string(vertex_count));
    }
    out[i] = static_cast<std::uint32_t>(v);
  }
  return {};
}

}  // namespace

// Reads accessor `index` as `count * components` numbers, decoded per read_component, with
// byteStride honoured and any sparse substitution applied.
Result<std::vector<double>> read_accessor(const ModelBytes& source, int index, int components,
                                          std::span<const int> allowed, bool may_normalize,
                                          const std::string& what) {
  Result<AccessorBytes> a = locate_accessor(source, index, components, allowed, may_normalize, what);
  if (!a) return std::unexpected(a.error());
  const auto n = static_cast<std::size_t>(components);
  const int type = a->accessor->componentType;
  const bool normalized = a->accessor->normalized;
  // Without a buffer view the base values are zeros (glTF 2.0 section 3.6.2.3).
  std::vector<double> values(a->count * n, 0.0);
  if (a->base != nullptr) {
    for (std::size_t i = 0; i < a->count; ++i) {
      const unsigned char* p = a->base + i * a->stride;
      for (std::size_t c = 0; c < n; ++c) values[i * n + c] = read_component(p + c * a->component, type, normalized);
    }
  }
  auto ok = substitute_sparse(*a, [&](std::size_t target, const unsigned char* p) {
    for (std::size_t c = 0; c < n; ++c) values[target * n + c] = read_component(p + c * a->component, type, normalized);
  });
  if (!ok) return std::unexpected(ok.error());
  return values;
}

Result<std::vector<glm::dvec3>> read_vec3(const ModelBytes& source, int index, std::span<const int> allowed,
                                          bool may_normalize, const std::string& what, AccessorPath path) {
  if (path == AccessorPath::Generic) {
    Result<std::vector<double>> values = read_accessor(source, index, 3, allowed, may_normalize, what);
    if (!values) return std::unexpected(values.error());
    std::vector<glm::dvec3> out(values->size() / 3);
    for (std::size_t v = 0; v < out.size(); ++v) out[v] = glm::make_vec3(&(*values)[3 * v]);
    return out;
  }
  Result<AccessorBytes> a = locate_accessor(source, index, 3, allowed, may_normalize, what);
  if (!a) return std::unexpected(a.error());
  // A big mesh's positions are written once, front to back: huge pages fault 512 times less.
  std::vector<glm::dvec3> out;
  reserve_huge(out, a->count);
  out.resize(a->count, glm::dvec3(0.0));
  if (a->base != nullptr) decode_vec3(*a, out);
  const int type = a->accessor->componentType;
  const bool normalized = a->accessor->normalized;
  auto ok = substitute_sparse(*a, [&](std::size_t target, const unsigned char* p) {
    out[target] = glm::dvec3(read_component(p, type, normalized), read_component(p + a->component, type, normalized),
                             read_component(p + 2 * a->component, type, normalized));
  });
  if (!ok) return std::unexpected(ok.error());
  return out;
}

Result<std::vector<std::uint32_t>> read_indices(const ModelBytes& source, int index, std::size_t vertex_count,
                                                const std::string& where, AccessorPath path) {
  const std::string what = where + " indices";
  Result<AccessorBytes> a = locate_accessor(source, index, 1, kIndexTypes, false, what);
  if (!a) return std::unexpected(a.error());
  std::vector<std::uint32_t> out;
  // Sparse or view-less indices are rare: they take the generic reading.
  if (path == AccessorPath::Generic || a->base == nullptr || a->sparse_count > 0) {
    Result<std::vector<double>> values = read_accessor(source, index, 1, kIndexTypes, false, what);
    if (!values) return std::unexpected(values.error());
    out.reserve(values->size());
    for (const double i : *values) {
      if (i >= static_cast<double>(vertex_count)) {
        return fail(where + ": index " + std::to_string(static_cast<std::uint64_t>(i)) + " >= vertex count " +
                    std::to_string(vertex_count));
      }
      out.push_back(static_cast<std::uint32_t>(i));
    }
    return out;
  }
  reserve_huge(out, a->count);
  out.resize(a->count);
  Result<void> ok;
  switch (a->accessor->componentType) {
    case kUnsignedByte: ok = decode_indices<std::uint8_t>(*a, vertex_count, where, out.data()); break;
    case kUnsignedShort: ok = decode_indices<std::uint16_t>(*a, vertex_count, where, out.data()); break;
    default: ok = decode_indices<std::uint32_t>(*a, vertex_count, where, out.data()); break;  // kIndexTypes
  }
  if (!ok) return std::unexpected(ok.error());
  return out;
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

// Per-instance local transforms from EXT_mesh_gpu_instancing, or one identity when the node
// has none. Each row is T * R * S, applied before the node's world matrix.
Result<std::vector<glm::dmat4>> instance_transforms(const ModelBytes& source,
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
        read_accessor(source, v.GetNumberAsInt(), widths[k], types, true, where + " " + names[k]);
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

}  // namespace exao::gltf
