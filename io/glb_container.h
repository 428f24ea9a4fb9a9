#pragma once
// exao::gltf: the GLB container's words (glTF 2.0 section 4.4): a 12-byte header (magic, version,
// length), then chunks of a length, a type and the bytes, every word little-endian. Shared by
// the readers that look inside a GLB before tinygltf does and those that write one for it.
// Internal to io/.

#include <cstdint>
#include <string_view>
#include <vector>

namespace exao::gltf {

inline constexpr std::uint32_t kGlbMagic = 0x46546C67u;  // "glTF"
inline constexpr std::uint32_t kJsonChunk = 0x4E4F534Au;  // "JSON"
inline constexpr std::uint32_t kBinChunk = 0x004E4942u;   // "BIN\0"

/// The little-endian word at `p`.
[[nodiscard]] inline std::uint32_t glb_word(const unsigned char* p) {
  return std::uint32_t{p[0]} | std::uint32_t{p[1]} << 8 | std::uint32_t{p[2]} << 16 | std::uint32_t{p[3]} << 24;
}

/// Appends `v` as a little-endian word.
inline void append_glb_word(std::vector<unsigned char>& out, std::uint32_t v) {
  for (int k = 0; k < 4; ++k) out.push_back(static_cast<unsigned char>(v >> (8 * k)));
}

/// A GLB's header and JSON chunk (`json`, padded with spaces to a multiple of 4) into `out`, for
/// a container of `rest` more bytes that the caller appends.
inline void start_glb(std::vector<unsigned char>& out, std::string_view json, std::size_t rest) {
  const std::size_t padded = (json.size() + 3) / 4 * 4;
  append_glb_word(out, kGlbMagic);
  append_glb_word(out, 2);
  append_glb_word(out, static_cast<std::uint32_t>(20 + padded + rest));
  append_glb_word(out, static_cast<std::uint32_t>(padded));
  append_glb_word(out, kJsonChunk);
  out.insert(out.end(), json.begin(), json.end());
  out.insert(out.end(), padded - json.size(), ' ');
}

}  // namespace exao::gltf
