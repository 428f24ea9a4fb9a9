#include "io/glb_in_place.h"

#include <algorithm>
#include <array>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "io/glb_container.h"

namespace exao::gltf {
namespace {

// Extensions whose decoders (io/gltf_compression.h) read and rewrite the model's buffers.
constexpr std::array<std::string_view, 3> kRewrites{"KHR_draco_mesh_compression", "EXT_meshopt_compression",
                                                    "KHR_meshopt_compression"};

// An unsigned integer member of `o`, or `fallback` when absent; nothing when it is not one.
std::optional<std::uint64_t> unsigned_member(const nlohmann::json& o, const char* name, std::uint64_t fallback) {
  const auto it = o.find(name);
  if (it == o.end()) return fallback;
  if (!it->is_number_unsigned()) return std::nullopt;
  return it->get<std::uint64_t>();
}

// Where the images stored in buffer 0 end (0 for none), or nothing when one is malformed or
// reaches past `length`.
std::optional<std::uint64_t> images_end(const nlohmann::json& json, std::uint64_t length) {
  std::uint64_t end = 0;
  const auto images = json.find("images");
  if (images == json.end()) return end;
  const auto views = json.find("bufferViews");
  if (!images->is_array()) return std::nullopt;
  for (const nlohmann::json& image : *images) {
    if (!image.is_object() || !image.contains("bufferView")) continue;
    const std::optional<std::uint64_t> v = unsigned_member(image, "bufferView", 0);
    if (!v || views == json.end() || !views->is_array() || *v >= views->size()) return std::nullopt;
    const nlohmann::json& view = (*views)[*v];
    if (!view.is_object()) return std::nullopt;
    const std::optional<std::uint64_t> buffer = unsigned_member(view, "buffer", UINT64_MAX);
    const std::optional<std::uint64_t> offset = unsigned_member(view, "byteOffset", 0);
    const std::optional<std::uint64_t> size = unsigned_member(view, "byteLength", UINT64_MAX);
    if (!buffer || !offset || !size || *size == UINT64_MAX) return std::nullopt;
    if (*buffer != 0) continue;
    if (*offset > length || *size > length - *offset) return std::nullopt;
    end = std::max(end, *offset + *size);
  }
  return end;
}

}  // namespace

std::optional<GlbInPlace> glb_in_place(std::span<const unsigned char> glb) {
  // glTF 2.0 section 4.4: a 12-byte header, the JSON chunk, then the BIN chunk.
  if (glb.size() < 20 || glb_word(glb.data()) != kGlbMagic || glb_word(glb.data() + 16) != kJsonChunk) return std::nullopt;
  const std::uint64_t json_length = glb_word(glb.data() + 12);
  if (json_length > glb.size() - 20) return std::nullopt;
  const std::uint64_t bin_at = (20 + json_length + 3) / 4 * 4;
  if (bin_at + 8 > glb.size() || glb_word(glb.data() + bin_at + 4) != kBinChunk) return std::nullopt;
  const std::uint64_t bin_length = glb_word(glb.data() + bin_at);
  if (bin_length > glb.size() - bin_at - 8) return std::nullopt;
  const std::string_view text(reinterpret_cast<const char*>(glb.data() + 20), json_length);
  for (const std::string_view name : kRewrites)
    if (text.find(name) != std::string_view::npos) return std::nullopt;

  nlohmann::ordered_json json = nlohmann::ordered_json::parse(text, nullptr, false);
  if (json.is_discarded() || !json.is_object()) return std::nullopt;
  const auto buffers = json.find("buffers");
  if (buffers == json.end() || !buffers->is_array() || buffers->empty()) return std::nullopt;
  nlohmann::ordered_json& buffer = (*buffers)[0];
  if (!buffer.is_object() || buffer.contains("uri")) return std::nullopt;
  // tinygltf gives every buffer without a URI the BIN chunk; only buffer 0 may be that one here.
  for (std::size_t i = 1; i < buffers->size(); ++i)
    if (!(*buffers)[i].is_object() || !(*buffers)[i].contains("uri")) return std::nullopt;
  const std::optional<std::uint64_t> length = unsigned_member(buffer, "byteLength", UINT64_MAX);
  if (!length || *length == 0 || *length > bin_length) return std::nullopt;
  const std::optional<std::uint64_t> kept = images_end(json, *length);
  if (!kept) return std::nullopt;

  const std::uint64_t keep = std::max<std::uint64_t>(*kept, 1);
  buffer["byteLength"] = keep;
  std::string patched;
  try {
    patched = json.dump();
  } catch (const nlohmann::json::exception&) {  // a string that is not UTF-8: tinygltf will say so
    return std::nullopt;
  }
  const std::uint64_t chunk = std::min((keep + 3) / 4 * 4, bin_length);
  GlbInPlace out;
  std::vector<unsigned char>& c = out.container;
  c.reserve(28 + patched.size() + 3 + chunk);
  start_glb(c, patched, 8 + chunk);
  append_glb_word(c, static_cast<std::uint32_t>(chunk));
  append_glb_word(c, kBinChunk);
  c.insert(c.end(), glb.data() + bin_at + 8, glb.data() + bin_at + 8 + chunk);
  out.buffer0 = glb.subspan(bin_at + 8, *length);
  return out;
}

}  // namespace exao::gltf
