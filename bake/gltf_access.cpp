#include "bake/gltf_access.h"

#include <algorithm>
#include <cstring>
#include <limits>

namespace exao::bake {
namespace {

// An accessor without a buffer view (zeros plus sparse values) has no bytes to bound its count;
// the same cap as core/gltf_loader.cpp, far beyond any real sparse-only accessor.
constexpr std::size_t kMaxViewlessCount = std::size_t{1} << 24;

// The name of the buffer the bake appends to; it never reaches a written file (save merges it).
constexpr const char* kAppendBuffer = "exao-bake-appended";

int component_size(int component_type) {
  switch (component_type) {
    case kByte:
    case kUnsignedByte: return 1;
    case kShort:
    case kUnsignedShort: return 2;
    case kUnsignedInt:
    case kFloat: return 4;
    default: return 0;
  }
}

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
    default: {
      float v;
      std::memcpy(&v, p, sizeof v);
      return v;
    }
  }
}

// Whether `count` elements of `element` bytes, `stride` apart, from `offset`, fit in `length`
// bytes; no intermediate value can overflow.
bool fits(std::size_t offset, std::size_t count, std::size_t stride, std::size_t element, std::size_t length) {
  if (count == 0) return offset <= length;
  if (element > length || offset > length - element) return false;
  return stride == 0 || count - 1 <= (length - element - offset) / stride;
}

Result<const unsigned char*> view_bytes(const tinygltf::Model& model, int view_index, std::size_t offset,
                                        std::size_t count, std::size_t stride, std::size_t element,
                                        const std::string& what) {
  if (view_index < 0 || static_cast<std::size_t>(view_index) >= model.bufferViews.size()) {
    return fail(what + " refers to buffer view " + std::to_string(view_index) + ", file has " +
                std::to_string(model.bufferViews.size()));
  }
  const tinygltf::BufferView& view = model.bufferViews[static_cast<std::size_t>(view_index)];
  if (view.buffer < 0 || static_cast<std::size_t>(view.buffer) >= model.buffers.size()) {
    return fail("buffer view " + std::to_string(view_index) + " refers to buffer " + std::to_string(view.buffer) +
                ", file has " + std::to_string(model.buffers.size()));
  }
  const std::vector<unsigned char>& data = model.buffers[static_cast<std::size_t>(view.buffer)].data;
  if (!fits(view.byteOffset, 1, 0, view.byteLength, data.size())) {
    return fail("buffer view " + std::to_string(view_index) + " exceeds buffer " + std::to_string(view.buffer) +
                " (" + std::to_string(data.size()) + " bytes)");
  }
  if (!fits(offset, count, stride, element, view.byteLength)) {
    return fail(what + " (" + std::to_string(count) + " elements from byte " + std::to_string(offset) +
                ") exceeds its buffer view " + std::to_string(view_index));
  }
  return data.data() + view.byteOffset + offset;
}

int appended_buffer(tinygltf::Model& model) {
  for (std::size_t i = 0; i < model.buffers.size(); ++i) {
    if (model.buffers[i].name == kAppendBuffer) return static_cast<int>(i);
  }
  tinygltf::Buffer buffer;
  buffer.name = kAppendBuffer;
  model.buffers.push_back(std::move(buffer));
  return static_cast<int>(model.buffers.size() - 1);
}

}  // namespace

std::string one_line(const std::string& text) {
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

int accessor_components(const tinygltf::Model& model, int index) {
  if (index < 0 || static_cast<std::size_t>(index) >= model.accessors.size()) return 0;
  const int n = tinygltf::GetNumComponentsInType(
      static_cast<std::uint32_t>(model.accessors[static_cast<std::size_t>(index)].type));
  return n < 0 ? 0 : n;
}

Result<std::vector<double>> read_accessor(const tinygltf::Model& model, int index, int components,
                                          std::span<const int> allowed, bool may_normalize, const std::string& what) {
  if (index < 0 || static_cast<std::size_t>(index) >= model.accessors.size()) {
    return fail(what + " refers to accessor " + std::to_string(index) + ", file has " +
                std::to_string(model.accessors.size()));
  }
  const tinygltf::Accessor& acc = model.accessors[static_cast<std::size_t>(index)];
  const std::string name = "accessor " + std::to_string(index) + " (" + what + ")";
  if (accessor_components(model, index) != components) {
    return fail(name + " has " + std::to_string(accessor_components(model, index)) + " components, expected " +
                std::to_string(components));
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
  const unsigned char* base = nullptr;
  std::size_t stride = element;
  if (acc.bufferView >= 0) {
    if (static_cast<std::size_t>(acc.bufferView) < model.bufferViews.size()) {
      const std::size_t given = model.bufferViews[static_cast<std::size_t>(acc.bufferView)].byteStride;
      if (given != 0) stride = given;
    }
    if (stride < element) return fail(name + ": byteStride " + std::to_string(stride) + " is less than an element");
    auto bytes = view_bytes(model, acc.bufferView, acc.byteOffset, acc.count, stride, element, name);
    if (!bytes) return std::unexpected(bytes.error());
    base = *bytes;
  }
  // Without a buffer view the base values are zeros (glTF 2.0 section 3.6.2.3).
  std::vector<double> values(acc.count * n, 0.0);
  if (base != nullptr) {
    for (std::size_t i = 0; i < acc.count; ++i) {
      const unsigned char* p = base + i * stride;
      for (std::size_t c = 0; c < n; ++c) values[i * n + c] = read_component(p + c * size, acc.componentType, acc.normalized);
    }
  }
  if (acc.sparse.isSparse) {
    const int count = acc.sparse.count;
    const int index_type = acc.sparse.indices.componentType;
    if (count < 0 || static_cast<std::size_t>(count) > acc.count) return fail(name + ": sparse count exceeds count");
    if (std::find(kIndexTypes.begin(), kIndexTypes.end(), index_type) == kIndexTypes.end()) {
      return fail(name + ": sparse indices have unsupported component type " + std::to_string(index_type));
    }
    if (acc.sparse.indices.byteOffset < 0 || acc.sparse.values.byteOffset < 0) {
      return fail(name + ": negative sparse byteOffset");
    }
    const auto sparse_count = static_cast<std::size_t>(count);
    const auto index_size = static_cast<std::size_t>(component_size(index_type));
    auto index_bytes = view_bytes(model, acc.sparse.indices.bufferView,
                                  static_cast<std::size_t>(acc.sparse.indices.byteOffset), sparse_count, index_size,
                                  index_size, name + " sparse indices");
    if (!index_bytes) return std::unexpected(index_bytes.error());
    auto value_bytes = view_bytes(model, acc.sparse.values.bufferView,
                                  static_cast<std::size_t>(acc.sparse.values.byteOffset), sparse_count, element,
                                  element, name + " sparse values");
    if (!value_bytes) return std::unexpected(value_bytes.error());
    for (std::size_t i = 0; i < sparse_count; ++i) {
      const auto target = static_cast<std::size_t>(read_component(*index_bytes + i * index_size, index_type, false));
      if (target >= acc.count) return fail(name + ": sparse index " + std::to_string(target) + " >= count");
      for (std::size_t c = 0; c < n; ++c) {
        values[target * n + c] = read_component(*value_bytes + i * element + c * size, acc.componentType, acc.normalized);
      }
    }
  }
  return values;
}

int append_buffer_view(tinygltf::Model& model, std::span<const std::uint8_t> bytes, int target) {
  const int buffer_index = appended_buffer(model);
  std::vector<unsigned char>& data = model.buffers[static_cast<std::size_t>(buffer_index)].data;
  data.resize((data.size() + 3) / 4 * 4, 0);  // 4-byte alignment for every vertex attribute
  tinygltf::BufferView view;
  view.buffer = buffer_index;
  view.byteOffset = data.size();
  view.byteLength = bytes.size();
  view.target = target;
  data.insert(data.end(), bytes.begin(), bytes.end());
  model.bufferViews.push_back(std::move(view));
  return static_cast<int>(model.bufferViews.size() - 1);
}

int append_float_accessor(tinygltf::Model& model, std::span<const float> values, int components) {
  const auto n = static_cast<std::size_t>(components);
  std::vector<std::uint8_t> bytes(values.size() * sizeof(float));
  std::memcpy(bytes.data(), values.data(), bytes.size());
  tinygltf::Accessor acc;
  acc.bufferView = append_buffer_view(model, bytes, TINYGLTF_TARGET_ARRAY_BUFFER);
  acc.componentType = kFloat;
  acc.count = values.size() / n;
  acc.type = components == 1   ? TINYGLTF_TYPE_SCALAR
             : components == 2 ? TINYGLTF_TYPE_VEC2
             : components == 3 ? TINYGLTF_TYPE_VEC3
                               : TINYGLTF_TYPE_VEC4;
  acc.minValues.assign(n, std::numeric_limits<double>::infinity());
  acc.maxValues.assign(n, -std::numeric_limits<double>::infinity());
  for (std::size_t i = 0; i < values.size(); ++i) {
    acc.minValues[i % n] = std::min(acc.minValues[i % n], static_cast<double>(values[i]));
    acc.maxValues[i % n] = std::max(acc.maxValues[i % n], static_cast<double>(values[i]));
  }
  if (acc.count == 0) {
    acc.minValues.clear();
    acc.maxValues.clear();
  }
  model.accessors.push_back(std::move(acc));
  return static_cast<int>(model.accessors.size() - 1);
}

int append_index_accessor(tinygltf::Model& model, std::span<const std::uint32_t> indices) {
  std::vector<std::uint8_t> bytes(indices.size() * sizeof(std::uint32_t));
  std::memcpy(bytes.data(), indices.data(), bytes.size());
  tinygltf::Accessor acc;
  acc.bufferView = append_buffer_view(model, bytes, TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
  acc.componentType = kUnsignedInt;
  acc.count = indices.size();
  acc.type = TINYGLTF_TYPE_SCALAR;
  model.accessors.push_back(std::move(acc));
  return static_cast<int>(model.accessors.size() - 1);
}

}  // namespace exao::bake
