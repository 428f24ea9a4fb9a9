#include "bake/gltf_access.h"

#include <algorithm>
#include <cstring>
#include <limits>

namespace exao::bake {
namespace {

// The name of the buffer the bake appends to; it never reaches a written file (save merges it).
constexpr const char* kAppendBuffer = "exao-bake-appended";
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

int accessor_components(const tinygltf::Model& model, int index) {
  if (index < 0 || static_cast<std::size_t>(index) >= model.accessors.size()) return 0;
  const int n = tinygltf::GetNumComponentsInType(
      static_cast<std::uint32_t>(model.accessors[static_cast<std::size_t>(index)].type));
  return n < 0 ? 0 : n;
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
