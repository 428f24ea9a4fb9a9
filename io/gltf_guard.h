#pragma once
// Guards put in front of tinygltf, for the inputs Debian's tinygltf 2.7 does not survive.
// Internal to the modules that read glTF (core's loader, bake/): it exposes tinygltf.
//
// 1. Nesting. tinygltf converts JSON to its own values recursively, so arrays nested some
//    ten thousand deep in `extras` overflow the stack (a 30 KB file kills the program). The
//    JSON text (a .gltf file, or a .glb's JSON chunk) is pre-scanned instead: deeper than
//    kMaxJsonDepth levels of [ and { is refused before tinygltf sees it. Real files nest
//    fewer than 20 levels; the scan is one pass over the bytes and allocates nothing.
// 2. Buffer and image URIs. tinygltf reads whatever a URI names: a folder gives
//    std::bad_alloc (its size is -1), a FIFO blocks forever (even its existence test opens
//    it). The file callbacks installed here refuse anything but a regular file, by name.

#include <cstddef>
#include <string>
#include <string_view>

#include <tiny_gltf.h>

#include "core/error.h"

namespace exao::gltf {

/// The deepest nesting of JSON arrays and objects exao lets tinygltf parse.
inline constexpr std::size_t kMaxJsonDepth = 256;

/// The deepest nesting of [ and { in `json`, outside strings (escapes honoured); stops
/// counting once it passes `limit`. Does not validate the JSON.
[[nodiscard]] std::size_t json_depth(std::string_view json, std::size_t limit = kMaxJsonDepth);

/// Fails when the glTF file at `path` (JSON, or GLB by its magic) nests deeper than
/// kMaxJsonDepth. A GLB whose header cannot be read is left for tinygltf to refuse.
[[nodiscard]] Result<void> check_json_depth(const std::string& path);

/// File callbacks for tinygltf that read only regular files, and say what else a URI names.
void install_safe_file_access(tinygltf::TinyGLTF& context);

}  // namespace exao::gltf
