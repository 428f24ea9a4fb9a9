#include "bake/uv_rewrite.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <vector>

#include "bake/gltf_access.h"

namespace exao::bake {
namespace {

constexpr std::array kAnyType{kByte, kUnsignedByte, kShort, kUnsignedShort, kUnsignedInt, kFloat};

// One decoded number back into its stored type: the inverse of glTF's normalisation
// (glTF 2.0 section 3.11), rounded to nearest and clamped to the type's range.
void encode(double v, int type, bool normalized, unsigned char* out) {
  const auto put = [&](auto x) { std::memcpy(out, &x, sizeof x); };
  const auto integer = [&](double lo, double hi, double scale) {
    return std::clamp(std::round(normalized ? v * scale : v), lo, hi);
  };
  switch (type) {
    case kByte: put(static_cast<std::int8_t>(integer(-127, 127, 127.0))); break;
    case kUnsignedByte: put(static_cast<std::uint8_t>(integer(0, 255, 255.0))); break;
    case kShort: put(static_cast<std::int16_t>(integer(-32767, 32767, 32767.0))); break;
    case kUnsignedShort: put(static_cast<std::uint16_t>(integer(0, 65535, 65535.0))); break;
    case kUnsignedInt: put(static_cast<std::uint32_t>(integer(0, 4294967295.0, 4294967295.0))); break;
    default: put(static_cast<float>(v)); break;
  }
}

// A copy of accessor `index` with element i taken from old element source[i].
Result<int> gather(tinygltf::Model& model, int index, std::span<const std::uint32_t> source, std::size_t vertex_count,
                   const std::string& what) {
  const int components = accessor_components(model, index);
  if (components == 0) return fail(what + " has an unknown type");
  auto values = read_accessor(ModelBytes(model), index, components, kAnyType, true, what);
  if (!values) return std::unexpected(values.error());
  const auto n = static_cast<std::size_t>(components);
  if (values->size() != vertex_count * n) return fail(what + " has a different count than POSITION");
  const tinygltf::Accessor old = model.accessors[static_cast<std::size_t>(index)];
  const auto size = static_cast<std::size_t>(tinygltf::GetComponentSizeInBytes(static_cast<std::uint32_t>(old.componentType)));
  const std::size_t element = n * size;
  const std::size_t stride = (element + 3) / 4 * 4;  // vertex attributes: 4-byte aligned (glTF 2.0 section 3.6.2.4)
  std::vector<std::uint8_t> bytes(source.size() * stride, 0);
  std::vector<double> lo(n, std::numeric_limits<double>::infinity()), hi(n, -std::numeric_limits<double>::infinity());
  std::vector<unsigned char> stored(size);
  for (std::size_t i = 0; i < source.size(); ++i) {
    for (std::size_t c = 0; c < n; ++c) {
      unsigned char* at = bytes.data() + i * stride + c * size;
      encode((*values)[source[i] * n + c], old.componentType, old.normalized, at);
      // min / max are in the stored type (glTF 2.0 section 5.1.12): read back what was written.
      double v = 0.0;
      switch (old.componentType) {
        case kByte: v = static_cast<std::int8_t>(*at); break;
        case kUnsignedByte: v = *at; break;
        case kShort: { std::int16_t x; std::memcpy(&x, at, 2); v = x; break; }
        case kUnsignedShort: { std::uint16_t x; std::memcpy(&x, at, 2); v = x; break; }
        case kUnsignedInt: { std::uint32_t x; std::memcpy(&x, at, 4); v = x; break; }
        default: { float x; std::memcpy(&x, at, 4); v = x; break; }
      }
      lo[c] = std::min(lo[c], v);
      hi[c] = std::max(hi[c], v);
    }
  }
  tinygltf::Accessor acc;
  acc.name = old.name;
  acc.bufferView = append_buffer_view(model, bytes, TINYGLTF_TARGET_ARRAY_BUFFER);
  model.bufferViews[static_cast<std::size_t>(acc.bufferView)].byteStride = stride;
  acc.componentType = old.componentType;
  acc.normalized = old.normalized;
  acc.type = old.type;
  acc.count = source.size();
  if (!old.minValues.empty() && !source.empty()) acc.minValues = lo;
  if (!old.maxValues.empty() && !source.empty()) acc.maxValues = hi;
  model.accessors.push_back(std::move(acc));
  return static_cast<int>(model.accessors.size() - 1);
}

}  // namespace

Result<void> write_generated_uvs(tinygltf::Model& model, int mesh, int primitive, std::span<const std::uint32_t> source,
                                 std::span<const glm::vec2> uv, std::span<const std::uint32_t> corners, int set,
                                 const std::string& label) {
  tinygltf::Primitive prim = model.meshes[static_cast<std::size_t>(mesh)].primitives[static_cast<std::size_t>(primitive)];
  const auto position = prim.attributes.find("POSITION");
  if (position == prim.attributes.end()) return fail(label + " has no POSITION");
  if (position->second < 0 || static_cast<std::size_t>(position->second) >= model.accessors.size()) {
    return fail(label + " POSITION refers to a missing accessor");
  }
  const std::size_t vertex_count = model.accessors[static_cast<std::size_t>(position->second)].count;
  for (const std::uint32_t s : source) {
    if (s >= vertex_count) return fail(label + ": generated vertex copies vertex " + std::to_string(s) + " of " + std::to_string(vertex_count));
  }
  // Gathered once per accessor: several attributes (or targets) may share one.
  std::map<int, int> copied;
  const auto copy = [&](int index, const std::string& what) -> Result<int> {
    const auto found = copied.find(index);
    if (found != copied.end()) return found->second;
    auto made = gather(model, index, source, vertex_count, label + " " + what);
    if (!made) return std::unexpected(made.error());
    copied.emplace(index, *made);
    return *made;
  };
  for (auto& [name, index] : prim.attributes) {
    auto made = copy(index, name);
    if (!made) return std::unexpected(made.error());
    index = *made;
  }
  for (std::size_t t = 0; t < prim.targets.size(); ++t) {
    for (auto& [name, index] : prim.targets[t]) {
      auto made = copy(index, "morph target " + std::to_string(t) + " " + name);
      if (!made) return std::unexpected(made.error());
      index = *made;
    }
  }
  std::vector<float> flat(2 * uv.size());
  for (std::size_t i = 0; i < uv.size(); ++i) {
    flat[2 * i] = uv[i].x;
    flat[2 * i + 1] = uv[i].y;
  }
  const int uv_accessor = append_float_accessor(model, flat, 2);
  for (int k = 0; k <= set; ++k) {
    const std::string name = "TEXCOORD_" + std::to_string(k);
    if (k == set || prim.attributes.count(name) == 0) prim.attributes[name] = uv_accessor;
  }
  prim.indices = append_index_accessor(model, corners);
  prim.mode = TINYGLTF_MODE_TRIANGLES;
  model.meshes[static_cast<std::size_t>(mesh)].primitives[static_cast<std::size_t>(primitive)] = std::move(prim);
  return {};
}

}  // namespace exao::bake
