#pragma once
// Small glTF files written by the tests: one binary buffer holding every buffer view, written as a
// .gltf with a base64 data URI or as a .glb (shared by loaders_test and gltf_direct_test).

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

namespace exao::test {

inline constexpr int kUByte = 5121;
inline constexpr int kUShort = 5123;
inline constexpr int kUInt = 5125;
inline constexpr int kFloat = 5126;

inline std::string base64(const std::string& data) {
  static constexpr char kDigits[] =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  std::size_t i = 0;
  for (; i + 2 < data.size(); i += 3) {
    const unsigned v = (static_cast<unsigned char>(data[i]) << 16) |
                       (static_cast<unsigned char>(data[i + 1]) << 8) |
                       static_cast<unsigned char>(data[i + 2]);
    out += kDigits[(v >> 18) & 63];
    out += kDigits[(v >> 12) & 63];
    out += kDigits[(v >> 6) & 63];
    out += kDigits[v & 63];
  }
  if (i + 1 == data.size()) {
    const unsigned v = static_cast<unsigned char>(data[i]) << 16;
    out += kDigits[(v >> 18) & 63];
    out += kDigits[(v >> 12) & 63];
    out += "==";
  } else if (i + 2 == data.size()) {
    const unsigned v = (static_cast<unsigned char>(data[i]) << 16) |
                       (static_cast<unsigned char>(data[i + 1]) << 8);
    out += kDigits[(v >> 18) & 63];
    out += kDigits[(v >> 12) & 63];
    out += kDigits[(v >> 6) & 63];
    out += '=';
  }
  return out;
}

// The little-endian bytes of `values` (x86 and ARM are little-endian, like glTF).
template <class T>
inline std::string bytes(const std::vector<T>& values) {
  std::string out(values.size() * sizeof(T), '\0');
  if (!values.empty()) std::memcpy(out.data(), values.data(), out.size());
  return out;
}

// Builds small glTF files: one binary buffer holding every buffer view, written either as a
// .gltf with a base64 data URI or as a .glb.
class GltfWriter {
 public:
  // Appends `data` as a buffer view (4-byte aligned, as glTF requires) and returns its index.
  int view(const std::string& data, int stride = 0) {
    while (bin_.size() % 4 != 0) bin_ += '\0';
    std::string v = "{\"buffer\":0,\"byteOffset\":" + std::to_string(bin_.size()) +
                    ",\"byteLength\":" + std::to_string(data.size());
    if (stride != 0) v += ",\"byteStride\":" + std::to_string(stride);
    views_.push_back(v + "}");
    bin_ += data;
    return static_cast<int>(views_.size()) - 1;
  }
  // Adds an accessor; `extra` holds further JSON members (", \"normalized\":true" and so on).
  // A negative `view` leaves bufferView out.
  int accessor(int view_index, int component_type, std::size_t count, const std::string& type,
               const std::string& extra = "") {
    std::string a = "{";
    if (view_index >= 0) a += "\"bufferView\":" + std::to_string(view_index) + ",";
    a += "\"componentType\":" + std::to_string(component_type) +
         ",\"count\":" + std::to_string(count) + ",\"type\":\"" + type + "\"" + extra + "}";
    accessors_.push_back(a);
    return static_cast<int>(accessors_.size()) - 1;
  }
  // Adds a buffer view written out by hand, for views that break the rules.
  int raw_view(const std::string& json_object) {
    views_.push_back(json_object);
    return static_cast<int>(views_.size()) - 1;
  }
  int positions(const std::vector<float>& xyz) {
    return accessor(view(bytes(xyz)), kFloat, xyz.size() / 3, "VEC3");
  }
  template <class T>
  int indices(const std::vector<T>& values, int component_type) {
    return accessor(view(bytes(values)), component_type, values.size(), "SCALAR");
  }

  // `members`: the top-level JSON members other than asset, buffers, bufferViews, accessors.
  [[nodiscard]] std::string gltf(const std::string& members) const {
    return json(members, "\"uri\":\"data:application/octet-stream;base64," + base64(bin_) + "\",");
  }
  [[nodiscard]] std::string glb(const std::string& members) const {
    std::string text = json(members, "");
    while (text.size() % 4 != 0) text += ' ';
    std::string bin = bin_;
    while (bin.size() % 4 != 0) bin += '\0';
    std::string out;
    const auto u32 = [&out](std::uint32_t v) { out += bytes(std::vector<std::uint32_t>{v}); };
    out += "glTF";
    u32(2);
    u32(static_cast<std::uint32_t>(12 + 8 + text.size() + 8 + bin.size()));
    u32(static_cast<std::uint32_t>(text.size()));
    u32(0x4E4F534Au);  // "JSON"
    out += text;
    u32(static_cast<std::uint32_t>(bin.size()));
    u32(0x004E4942u);  // "BIN\0"
    out += bin;
    return out;
  }

 private:
  [[nodiscard]] std::string json(const std::string& members, const std::string& uri) const {
    std::string out = "{\"asset\":{\"version\":\"2.0\"},\"buffers\":[{" + uri +
                      "\"byteLength\":" + std::to_string(bin_.size()) + "}]";
    out += ",\"bufferViews\":[" + join(views_) + "]";
    out += ",\"accessors\":[" + join(accessors_) + "]";
    if (!members.empty()) {
      out += ',';
      out += members;
    }
    return out + "}";
  }
  static std::string join(const std::vector<std::string>& items) {
    std::string out;
    for (std::size_t i = 0; i < items.size(); ++i) {
      if (i != 0) out += ',';
      out += items[i];
    }
    return out;
  }
  std::string bin_;
  std::vector<std::string> views_;
  std::vector<std::string> accessors_;
};

}  // namespace exao::test
