#include "io/gltf_compression.h"

#include <draco/compression/decode.h>
#include <draco/mesh/mesh.h>
#include <meshoptimizer.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <limits>
#include <map>
#include <optional>
#include <span>
#include <string_view>

#include <nlohmann/json.hpp>

#include "io/glb_container.h"
#include "io/mapped_file.h"

namespace exao::gltf {
namespace {

constexpr std::array<std::string_view, 2> kMeshopt{"EXT_meshopt_compression", "KHR_meshopt_compression"};
constexpr std::string_view kDraco = "KHR_draco_mesh_compression";

// ---- Reading: the placeholder for meshopt fallback buffers --------------------------------------

// A data: URI of three zero bytes: tinygltf checks that a buffer's bytes match its byteLength.
constexpr const char* kPlaceholderUri = "data:application/octet-stream;base64,AAAA";
constexpr std::size_t kPlaceholderLength = 3;

bool is_fallback(const nlohmann::json& buffer) {
  if (!buffer.is_object() || buffer.contains("uri") || !buffer.contains("extensions")) return false;
  const nlohmann::json& ext = buffer["extensions"];
  if (!ext.is_object()) return false;
  for (const std::string_view name : kMeshopt) {
    const auto it = ext.find(std::string(name));
    if (it != ext.end() && it->is_object() && it->value("fallback", false) == true) return true;
  }
  return false;
}

// Makes a compressed file loadable by tinygltf 2.7, which rejects two things the extensions
// allow: a URI-less meshopt fallback buffer gets the placeholder, and a Draco primitive's index
// accessor without a buffer view ("accessor[i] invalid bufferView") points at the Draco stream's
// view, which decode_compression replaces before anything reads it. False when nothing changed
// (or the JSON does not parse: tinygltf will then say why).
bool patch_for_tinygltf(std::string& json_text) {
  if (json_text.find("fallback") == std::string::npos && json_text.find(kDraco) == std::string::npos) return false;
  nlohmann::ordered_json json = nlohmann::ordered_json::parse(json_text, nullptr, false);
  if (json.is_discarded() || !json.is_object()) return false;
  bool changed = false;
  if (json.contains("buffers") && json["buffers"].is_array()) {
    for (auto& buffer : json["buffers"]) {
      if (!is_fallback(buffer)) continue;
      buffer["uri"] = kPlaceholderUri;
      buffer["byteLength"] = kPlaceholderLength;
      changed = true;
    }
  }
  if (json.contains("meshes") && json["meshes"].is_array() && json.contains("accessors") && json["accessors"].is_array()) {
    auto& accessors = json["accessors"];
    for (auto& mesh : json["meshes"]) {
      if (!mesh.is_object() || !mesh.contains("primitives") || !mesh["primitives"].is_array()) continue;
      for (auto& prim : mesh["primitives"]) {
        if (!prim.is_object() || !prim.contains("indices") || !prim["indices"].is_number_unsigned()) continue;
        if (!prim.contains("extensions") || !prim["extensions"].is_object()) continue;
        const auto draco = prim["extensions"].find(std::string(kDraco));
        if (draco == prim["extensions"].end() || !draco->is_object() || !draco->contains("bufferView")) continue;
        const std::size_t index = prim["indices"].get<std::size_t>();
        if (index >= accessors.size() || !accessors[index].is_object() || accessors[index].contains("bufferView")) continue;
        accessors[index]["bufferView"] = (*draco)["bufferView"];
        changed = true;
      }
    }
  }
  if (changed) json_text = json.dump();
  return changed;
}

// ---- Writing decoded bytes -----------------------------------------------------------------------

// Where decoded bytes go: one new buffer, each piece 4-byte aligned (glTF 2.0 section 3.6.2.4).
struct Output {
  tinygltf::Model& model;
  int buffer = -1;
  // Appends the bytes; returns their offset in `buffer`.
  std::size_t append(const std::vector<unsigned char>& bytes) {
    if (buffer < 0) {
      model.buffers.emplace_back();
      buffer = static_cast<int>(model.buffers.size() - 1);
    }
    std::vector<unsigned char>& data = model.buffers[static_cast<std::size_t>(buffer)].data;
    data.resize((data.size() + 3) / 4 * 4, 0);
    const std::size_t at = data.size();
    data.insert(data.end(), bytes.begin(), bytes.end());
    return at;
  }
  // A new view of the bytes; returns its index.
  int view(const std::vector<unsigned char>& bytes, int target, int stride) {
    tinygltf::BufferView view;
    view.byteOffset = append(bytes);
    view.buffer = buffer;
    view.byteLength = bytes.size();
    view.byteStride = static_cast<std::size_t>(stride);
    view.target = target;
    model.bufferViews.push_back(std::move(view));
    return static_cast<int>(model.bufferViews.size() - 1);
  }
};

int component_bytes(int type) {
  const int size = tinygltf::GetComponentSizeInBytes(static_cast<std::uint32_t>(type));
  return size > 0 ? size : 0;
}

// Decodes one stored component back to a number (normalisation does not matter for min / max,
// which glTF states in the stored type).
double stored_component(const unsigned char* p, int type) {
  switch (type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE: return static_cast<double>(static_cast<std::int8_t>(*p));
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return static_cast<double>(*p);
    case TINYGLTF_COMPONENT_TYPE_SHORT: {
      std::int16_t v;
      std::memcpy(&v, p, sizeof v);
      return v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
      std::uint16_t v;
      std::memcpy(&v, p, sizeof v);
      return v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
      std::uint32_t v;
      std::memcpy(&v, p, sizeof v);
      return v;
    }
    default: {
      float v;
      std::memcpy(&v, p, sizeof v);
      return v;
    }
  }
}

// min / max of tightly packed elements, for an accessor that declared them.
void recompute_bounds(tinygltf::Accessor& accessor, const std::vector<unsigned char>& bytes, int components) {
  if (accessor.minValues.empty() && accessor.maxValues.empty()) return;
  const int size = component_bytes(accessor.componentType);
  const auto n = static_cast<std::size_t>(components);
  std::vector<double> lo(n, std::numeric_limits<double>::infinity()), hi(n, -std::numeric_limits<double>::infinity());
  for (std::size_t i = 0; i < accessor.count; ++i) {
    for (std::size_t c = 0; c < n; ++c) {
      const double v = stored_component(bytes.data() + (i * n + c) * static_cast<std::size_t>(size), accessor.componentType);
      lo[c] = std::min(lo[c], v);
      hi[c] = std::max(hi[c], v);
    }
  }
  if (accessor.count == 0) return;
  accessor.minValues = lo;
  accessor.maxValues = hi;
}

// ---- Draco -----------------------------------------------------------------------------------------

template <class T>
bool convert_attribute(const draco::PointAttribute& attribute, const draco::Mesh& mesh, int components,
                       std::vector<unsigned char>& out) {
  const auto n = static_cast<std::size_t>(components);
  out.assign(mesh.num_points() * n * sizeof(T), 0);
  std::vector<T> value(n);
  for (draco::PointIndex p(0); p < mesh.num_points(); ++p) {
    if (!attribute.ConvertValue<T>(attribute.mapped_index(p), static_cast<std::int8_t>(components), value.data())) {
      return false;
    }
    std::memcpy(out.data() + p.value() * n * sizeof(T), value.data(), n * sizeof(T));
  }
  return true;
}

bool convert(const draco::PointAttribute& attribute, const draco::Mesh& mesh, int component_type, int components,
             std::vector<unsigned char>& out) {
  switch (component_type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE: return convert_attribute<std::int8_t>(attribute, mesh, components, out);
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return convert_attribute<std::uint8_t>(attribute, mesh, components, out);
    case TINYGLTF_COMPONENT_TYPE_SHORT: return convert_attribute<std::int16_t>(attribute, mesh, components, out);
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return convert_attribute<std::uint16_t>(attribute, mesh, components, out);
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: return convert_attribute<std::uint32_t>(attribute, mesh, components, out);
    case TINYGLTF_COMPONENT_TYPE_FLOAT: return convert_attribute<float>(attribute, mesh, components, out);
    default: return false;
  }
}

// The bytes of the extension's buffer view, checked against the model's views and buffers.
Result<std::span<const unsigned char>> draco_stream(const tinygltf::Model& model, const tinygltf::Value& ext,
                                                    const std::string& where) {
  if (!ext.IsObject() || !ext.Has("bufferView") || !ext.Get("bufferView").IsNumber() || !ext.Has("attributes") ||
      !ext.Get("attributes").IsObject()) {
    return fail(where + " has no bufferView or attributes");
  }
  const int view_index = ext.Get("bufferView").GetNumberAsInt();
  if (view_index < 0 || static_cast<std::size_t>(view_index) >= model.bufferViews.size()) {
    return fail(where + " refers to buffer view " + std::to_string(view_index) + ", file has " +
                std::to_string(model.bufferViews.size()));
  }
  const tinygltf::BufferView& view = model.bufferViews[static_cast<std::size_t>(view_index)];
  if (view.buffer < 0 || static_cast<std::size_t>(view.buffer) >= model.buffers.size()) {
    return fail(where + ": buffer view " + std::to_string(view_index) + " refers to a missing buffer");
  }
  const std::vector<unsigned char>& data = model.buffers[static_cast<std::size_t>(view.buffer)].data;
  if (view.byteOffset > data.size() || view.byteLength > data.size() - view.byteOffset) {
    return fail(where + ": buffer view " + std::to_string(view_index) + " exceeds its buffer");
  }
  return std::span<const unsigned char>(data.data() + view.byteOffset, view.byteLength);
}

// A decoded attribute into its glTF accessor: converted to the accessor's type, bounds
// recomputed, in a new buffer view of a 4-byte aligned stride.
Result<void> fill_draco_attribute(const draco::PointAttribute& attribute, const draco::Mesh& mesh,
                                  tinygltf::Accessor& accessor, Output& output, const std::string& what) {
  const std::size_t points = mesh.num_points();
  const int components = tinygltf::GetNumComponentsInType(static_cast<std::uint32_t>(accessor.type));
  if (components < 1 || components > 4 || component_bytes(accessor.componentType) == 0) {
    return fail(what + " has an accessor type Draco cannot fill");
  }
  std::vector<unsigned char> bytes;
  if (!convert(attribute, mesh, accessor.componentType, components, bytes)) {
    return fail(what + " cannot be converted to its accessor's type");
  }
  accessor.count = points;
  accessor.byteOffset = 0;
  accessor.sparse = {};
  recompute_bounds(accessor, bytes, components);
  const int element = components * component_bytes(accessor.componentType);
  // Vertex attribute views need a 4-byte aligned stride (glTF 2.0 section 3.6.2.4).
  if (element % 4 != 0) {
    const std::size_t padded = static_cast<std::size_t>((element + 3) / 4 * 4);
    std::vector<unsigned char> strided(points * padded, 0);
    for (std::size_t i = 0; i < points; ++i) {
      std::memcpy(strided.data() + i * padded, bytes.data() + i * static_cast<std::size_t>(element), static_cast<std::size_t>(element));
    }
    accessor.bufferView = output.view(std::move(strided), TINYGLTF_TARGET_ARRAY_BUFFER, static_cast<int>(padded));
  } else {
    accessor.bufferView = output.view(std::move(bytes), TINYGLTF_TARGET_ARRAY_BUFFER, element);
  }
  return {};
}

// The decoded faces into the primitive's index accessor: the accessor's index type, unless a
// point index does not fit it.
void fill_draco_indices(const draco::Mesh& mesh, tinygltf::Accessor& accessor, Output& output) {
  const std::size_t points = mesh.num_points();
  int type = accessor.componentType;
  if (type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE && type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT) {
    type = TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
  }
  if ((type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE && points > 0xffu) ||
      (type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT && points > 0xffffu)) {
    type = TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
  }
  const auto size = static_cast<std::size_t>(component_bytes(type));
  std::vector<unsigned char> bytes(static_cast<std::size_t>(mesh.num_faces()) * 3 * size, 0);
  std::size_t at = 0;
  for (draco::FaceIndex f(0); f < mesh.num_faces(); ++f) {
    for (const draco::PointIndex& p : mesh.face(f)) {
      const std::uint32_t v = p.value();
      std::memcpy(bytes.data() + at, &v, size);  // little-endian: the low bytes first
      at += size;
    }
  }
  accessor.componentType = type;
  accessor.type = TINYGLTF_TYPE_SCALAR;
  accessor.count = static_cast<std::size_t>(mesh.num_faces()) * 3;
  accessor.byteOffset = 0;
  accessor.sparse = {};
  accessor.normalized = false;
  recompute_bounds(accessor, bytes, 1);
  accessor.bufferView = output.view(std::move(bytes), TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER, 0);
}

Result<void> decode_draco(tinygltf::Model& model, std::size_t mesh_index, std::size_t prim_index, Output& output,
                          std::vector<bool>& decoded_accessor) {
  tinygltf::Primitive& prim = model.meshes[mesh_index].primitives[prim_index];
  const std::string where = "mesh " + std::to_string(mesh_index) + " primitive " + std::to_string(prim_index) + " " +
                            std::string(kDraco);
  const tinygltf::Value& ext = prim.extensions.at(std::string(kDraco));
  Result<std::span<const unsigned char>> data = draco_stream(model, ext, where);
  if (!data) return std::unexpected(data.error());
  draco::DecoderBuffer stream;
  stream.Init(reinterpret_cast<const char*>(data->data()), data->size());
  draco::Decoder decoder;
  auto decoded = decoder.DecodeMeshFromBuffer(&stream);
  if (!decoded.ok()) return fail(where + " does not decode: " + decoded.status().error_msg_string());
  const std::unique_ptr<draco::Mesh> mesh = std::move(decoded).value();

  const tinygltf::Value& attributes = ext.Get("attributes");
  for (const std::string& name : attributes.Keys()) {
    const tinygltf::Value& id = attributes.Get(name);
    const auto target = prim.attributes.find(name);
    if (!id.IsNumber() || target == prim.attributes.end()) continue;  // the glTF attribute decides what is kept
    const int accessor_index = target->second;
    if (accessor_index < 0 || static_cast<std::size_t>(accessor_index) >= model.accessors.size()) {
      return fail(where + ": " + name + " refers to accessor " + std::to_string(accessor_index) + ", file has " +
                  std::to_string(model.accessors.size()));
    }
    if (decoded_accessor[static_cast<std::size_t>(accessor_index)]) continue;  // shared with a primitive decoded already
    const draco::PointAttribute* attribute = mesh->GetAttributeByUniqueId(static_cast<std::uint32_t>(id.GetNumberAsInt()));
    if (attribute == nullptr) return fail(where + ": " + name + " has no attribute " + std::to_string(id.GetNumberAsInt()) + " in the stream");
    tinygltf::Accessor& accessor = model.accessors[static_cast<std::size_t>(accessor_index)];
    if (auto ok = fill_draco_attribute(*attribute, *mesh, accessor, output, where + ": " + name); !ok) return ok;
    decoded_accessor[static_cast<std::size_t>(accessor_index)] = true;
  }

  if (prim.indices >= 0) {
    if (static_cast<std::size_t>(prim.indices) >= model.accessors.size()) {
      return fail(where + ": indices refer to accessor " + std::to_string(prim.indices) + ", file has " +
                  std::to_string(model.accessors.size()));
    }
    if (!decoded_accessor[static_cast<std::size_t>(prim.indices)]) {
      fill_draco_indices(*mesh, model.accessors[static_cast<std::size_t>(prim.indices)], output);
      decoded_accessor[static_cast<std::size_t>(prim.indices)] = true;
    }
  }
  prim.extensions.erase(std::string(kDraco));
  return {};
}

// ---- meshopt ---------------------------------------------------------------------------------------

std::size_t size_field(const tinygltf::Value& ext, const char* key, std::size_t fallback) {
  if (!ext.Has(key) || !ext.Get(key).IsNumber()) return fallback;
  const double v = ext.Get(key).GetNumberAsDouble();
  return v >= 0.0 && v < 9.0e15 ? static_cast<std::size_t>(v) : std::numeric_limits<std::size_t>::max();
}

// Decodes view `index` (glTF extension `name`) into a byte vector of count * byteStride bytes.
Result<std::vector<unsigned char>> decode_meshopt_view(const tinygltf::Model& model, std::size_t index,
                                                       const std::string& name, const tinygltf::Value& ext) {
  const std::string where = "buffer view " + std::to_string(index) + " " + name;
  if (!ext.IsObject() || !ext.Has("buffer") || !ext.Get("buffer").IsNumber()) return fail(where + " has no buffer");
  const int buffer = ext.Get("buffer").GetNumberAsInt();
  if (buffer < 0 || static_cast<std::size_t>(buffer) >= model.buffers.size()) {
    return fail(where + " refers to buffer " + std::to_string(buffer) + ", file has " + std::to_string(model.buffers.size()));
  }
  const std::size_t offset = size_field(ext, "byteOffset", 0);
  const std::size_t length = size_field(ext, "byteLength", std::numeric_limits<std::size_t>::max());
  const std::size_t stride = size_field(ext, "byteStride", 0);
  const std::size_t count = size_field(ext, "count", std::numeric_limits<std::size_t>::max());
  const std::string mode = ext.Has("mode") && ext.Get("mode").IsString() ? ext.Get("mode").Get<std::string>() : "";
  const std::string filter = ext.Has("filter") && ext.Get("filter").IsString() ? ext.Get("filter").Get<std::string>() : "NONE";
  const std::vector<unsigned char>& data = model.buffers[static_cast<std::size_t>(buffer)].data;
  if (offset > data.size() || length > data.size() - offset) {
    return fail(where + ": bytes " + std::to_string(offset) + "+" + std::to_string(length) + " exceed buffer " +
                std::to_string(buffer) + " (" + std::to_string(data.size()) + " bytes)");
  }
  // The extension's limits: strides of 1 to 256 bytes; the decoders themselves need no more.
  if (stride == 0 || stride > 256 || count == std::numeric_limits<std::size_t>::max()) {
    return fail(where + " has byteStride " + std::to_string(stride) + " or no count");
  }
  // A hostile count would make the output huge: the vertex codec needs at least a byte per
  // element per 16 elements, the index codecs about a byte per index.
  if (count / 64 > length + 1) return fail(where + ": count " + std::to_string(count) + " is too large for its bytes");
  std::vector<unsigned char> out(count * stride, 0);
  const unsigned char* source = data.data() + offset;
  int status = -1;
  if (mode == "ATTRIBUTES") {
    if (stride % 4 != 0) return fail(where + ": ATTRIBUTES need a byteStride that is a multiple of 4, got " + std::to_string(stride));
    status = meshopt_decodeVertexBuffer(out.data(), count, stride, source, length);
  } else if (mode == "TRIANGLES" || mode == "INDICES") {
    if (stride != 2 && stride != 4) return fail(where + ": indices need a byteStride of 2 or 4, got " + std::to_string(stride));
    if (mode == "TRIANGLES" && count % 3 != 0) return fail(where + ": TRIANGLES count " + std::to_string(count) + " is not a multiple of 3");
    status = mode == "TRIANGLES" ? meshopt_decodeIndexBuffer(out.data(), count, stride, source, length)
                                 : meshopt_decodeIndexSequence(out.data(), count, stride, source, length);
  } else {
    return fail(where + " has unknown mode '" + mode + "'");
  }
  if (status != 0) {
    return fail(where + " does not decode (meshoptimizer " + std::to_string(MESHOPTIMIZER_VERSION / 100) + "." +
                std::to_string(MESHOPTIMIZER_VERSION % 100) + " error " + std::to_string(status) +
                "; the data may be damaged or use a newer codec version)");
  }
  if (filter == "NONE") return out;
  if (mode != "ATTRIBUTES") return fail(where + ": filter " + filter + " on indices");
  if (filter == "OCTAHEDRAL") {
    if (stride != 4 && stride != 8) return fail(where + ": OCTAHEDRAL needs a byteStride of 4 or 8");
    meshopt_decodeFilterOct(out.data(), count, stride);
  } else if (filter == "QUATERNION") {
    if (stride != 8) return fail(where + ": QUATERNION needs a byteStride of 8");
    meshopt_decodeFilterQuat(out.data(), count, stride);
  } else if (filter == "EXPONENTIAL") {
    meshopt_decodeFilterExp(out.data(), count, stride);
  } else {
    return fail(where + " uses filter " + filter + ", which meshoptimizer " + std::to_string(MESHOPTIMIZER_VERSION / 100) +
                "." + std::to_string(MESHOPTIMIZER_VERSION % 100) + " cannot decode");
  }
  return out;
}

// ---- Compaction --------------------------------------------------------------------------------

// Keeps only the buffer views something refers to, in order, in one buffer: the Draco streams,
// the compressed meshopt bytes and the fallback placeholders are dropped, so that a model saved
// afterwards holds no dead bytes.
Result<void> compact(tinygltf::Model& model) {
  std::vector<bool> used(model.bufferViews.size(), false);
  const auto mark = [&](int v) {
    if (v >= 0 && static_cast<std::size_t>(v) < used.size()) used[static_cast<std::size_t>(v)] = true;
  };
  for (const tinygltf::Accessor& a : model.accessors) {
    mark(a.bufferView);
    if (a.sparse.isSparse) {
      mark(a.sparse.indices.bufferView);
      mark(a.sparse.values.bufferView);
    }
  }
  for (const tinygltf::Image& image : model.images) mark(image.bufferView);
  std::vector<int> remap(model.bufferViews.size(), -1);
  std::vector<tinygltf::BufferView> views;
  std::vector<unsigned char> merged;
  for (std::size_t v = 0; v < model.bufferViews.size(); ++v) {
    if (!used[v]) continue;
    tinygltf::BufferView view = model.bufferViews[v];
    const bool valid = view.buffer >= 0 && static_cast<std::size_t>(view.buffer) < model.buffers.size();
    const std::vector<unsigned char>* data = valid ? &model.buffers[static_cast<std::size_t>(view.buffer)].data : nullptr;
    // 16-byte alignment keeps every accessor's own alignment, whatever its view's offset was.
    merged.resize((merged.size() + 15) / 16 * 16, 0);
    const std::size_t at = merged.size();
    if (data == nullptr || view.byteOffset > data->size() || view.byteLength > data->size() - view.byteOffset) {
      return fail("buffer view " + std::to_string(v) + " exceeds its buffer");
    }
    merged.insert(merged.end(), data->begin() + static_cast<std::ptrdiff_t>(view.byteOffset),
                  data->begin() + static_cast<std::ptrdiff_t>(view.byteOffset + view.byteLength));
    view.buffer = 0;
    view.byteOffset = at;
    remap[v] = static_cast<int>(views.size());
    views.push_back(std::move(view));
  }
  const auto fix = [&](int& v) {
    if (v >= 0 && static_cast<std::size_t>(v) < remap.size()) v = remap[static_cast<std::size_t>(v)];
  };
  for (tinygltf::Accessor& a : model.accessors) {
    fix(a.bufferView);
    if (a.sparse.isSparse) {
      fix(a.sparse.indices.bufferView);
      fix(a.sparse.values.bufferView);
    }
  }
  for (tinygltf::Image& image : model.images) fix(image.bufferView);
  model.bufferViews = std::move(views);
  tinygltf::Buffer buffer;
  buffer.data = std::move(merged);
  model.buffers.clear();
  model.buffers.push_back(std::move(buffer));
  return {};
}

void drop_extension(std::vector<std::string>& list, std::string_view name) {
  list.erase(std::remove(list.begin(), list.end(), std::string(name)), list.end());
}

}  // namespace

bool load_file(tinygltf::TinyGLTF& context, tinygltf::Model& model, std::string& err, std::string& warn,
               const std::string& path, bool binary) {
  // Mapped, not read: tinygltf copies the BIN chunk into its buffer once, from the page cache.
  const MappedFile file(path);
  if (!file.ok()) {
    err = "cannot read the file";
    return false;
  }
  const auto* data = reinterpret_cast<const unsigned char*>(file.bytes().data());
  const std::size_t size = file.bytes().size();
  const std::string base = std::filesystem::path(path).parent_path().string();
  const std::string base_dir = base.empty() ? "." : base;
  if (size > std::numeric_limits<unsigned int>::max()) {
    err = "file is larger than 4 GiB";
    return false;
  }
  if (binary) {
    // GLB (glTF 2.0 section 4.4): header, JSON chunk, optional BIN chunk; only the JSON changes.
    std::vector<unsigned char> rebuilt;
    if (size >= 20) {
      const std::size_t json_length = glb_word(data + 12);
      if (glb_word(data + 16) == kJsonChunk && json_length <= size - 20) {
        std::string json(data + 20, data + 20 + json_length);
        if (patch_for_tinygltf(json)) {
          const std::size_t rest = (20 + json_length + 3) / 4 * 4;  // the BIN chunk, as it was
          const std::size_t tail = rest < size ? size - rest : 0;
          start_glb(rebuilt, json, tail);
          if (tail > 0) rebuilt.insert(rebuilt.end(), data + rest, data + size);
          if (rebuilt.size() > std::numeric_limits<unsigned int>::max()) {
            err = "file is larger than 4 GiB";
            return false;
          }
        }
      }
    }
    if (!rebuilt.empty()) {
      return context.LoadBinaryFromMemory(&model, &err, &warn, rebuilt.data(), static_cast<unsigned int>(rebuilt.size()),
                                          base_dir);
    }
    return context.LoadBinaryFromMemory(&model, &err, &warn, data, static_cast<unsigned int>(size), base_dir);
  }
  std::string json(file.bytes());
  patch_for_tinygltf(json);
  if (json.size() > std::numeric_limits<unsigned int>::max()) {
    err = "file is larger than 4 GiB";
    return false;
  }
  return context.LoadASCIIFromString(&model, &err, &warn, json.data(), static_cast<unsigned int>(json.size()), base_dir);
}

Result<std::vector<std::string>> decode_compression(tinygltf::Model& model) {
  std::vector<std::string> notes;
  Output output{model};

  // meshopt first: a Draco stream never lives in a meshopt view, but a meshopt file's accessors
  // must be plain before anything reads them.
  std::map<std::string, std::size_t> meshopt_views;
  for (std::size_t v = 0; v < model.bufferViews.size(); ++v) {
    for (const std::string_view name : kMeshopt) {
      const auto it = model.bufferViews[v].extensions.find(std::string(name));
      if (it == model.bufferViews[v].extensions.end()) continue;
      auto bytes = decode_meshopt_view(model, v, std::string(name), it->second);
      if (!bytes) return std::unexpected(bytes.error());
      // The view keeps its byteStride and target; only where its bytes are changes.
      const std::size_t at = output.append(*bytes);
      tinygltf::BufferView& view = model.bufferViews[v];
      view.buffer = output.buffer;
      view.byteOffset = at;
      view.byteLength = bytes->size();
      view.extensions.erase(std::string(name));
      ++meshopt_views[std::string(name)];
      break;
    }
  }

  std::size_t draco_primitives = 0;
  std::vector<bool> decoded_accessor(model.accessors.size(), false);
  for (std::size_t m = 0; m < model.meshes.size(); ++m) {
    for (std::size_t p = 0; p < model.meshes[m].primitives.size(); ++p) {
      if (model.meshes[m].primitives[p].extensions.count(std::string(kDraco)) == 0) continue;
      if (auto ok = decode_draco(model, m, p, output, decoded_accessor); !ok) return std::unexpected(ok.error());
      ++draco_primitives;
    }
  }

  if (draco_primitives == 0 && meshopt_views.empty()) return notes;
  if (auto ok = compact(model); !ok) return std::unexpected(ok.error());
  if (draco_primitives > 0) {
    drop_extension(model.extensionsUsed, kDraco);
    drop_extension(model.extensionsRequired, kDraco);
    notes.push_back(std::string(kDraco) + ": " + std::to_string(draco_primitives) +
                    " primitive(s) decoded with Draco (a bake writes them uncompressed, without the extension)");
  }
  for (const auto& [name, count] : meshopt_views) {
    drop_extension(model.extensionsUsed, name);
    drop_extension(model.extensionsRequired, name);
    notes.push_back(name + ": " + std::to_string(count) +
                    " buffer view(s) decoded with meshoptimizer (a bake writes them uncompressed, without the extension)");
  }
  return notes;
}

}  // namespace exao::gltf
