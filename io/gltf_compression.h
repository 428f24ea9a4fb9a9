#pragma once
// exao::gltf: compressed glTF geometry, decoded with Debian's libraries so that every command
// (info, render, query, bake) reads such files like any other. Internal: it exposes tinygltf.
//
// - KHR_draco_mesh_compression (libdraco): a primitive's attributes and indices live in one
//   Draco bit stream; its accessors carry only count and type.
// - EXT_meshopt_compression and KHR_meshopt_compression (libmeshoptimizer): a buffer view's
//   bytes are compressed elsewhere (vertex codec, index codec, optional filters), and the
//   buffer the view names is usually a "fallback" buffer with no bytes at all.
//
// After decode_compression the model is an ordinary one: accessors point at plain buffer views
// in one buffer, the extensions are gone from the primitives, the views and from
// extensionsUsed / extensionsRequired, so a writer that saves the model writes it uncompressed.

#include <tiny_gltf.h>

#include <string>
#include <vector>

#include "core/error.h"

namespace exao::gltf {

/// Reads `path` into `model` as tinygltf's LoadBinaryFromFile / LoadASCIIFromFile do (`binary`:
/// a GLB container), except for two things compressed files do that tinygltf 2.7 refuses: a
/// meshopt fallback buffer without a URI (it would take its bytes from the GLB's BIN chunk, or
/// fail to open "") gets a 3-byte placeholder, and a Draco index accessor without a buffer view
/// gets the Draco stream's view. Neither is ever read: decode_compression replaces both. Returns
/// tinygltf's result; its messages are in err and warn.
[[nodiscard]] bool load_file(tinygltf::TinyGLTF& context, tinygltf::Model& model, std::string& err, std::string& warn,
                             const std::string& path, bool binary);

/// Decodes every Draco primitive and every meshopt buffer view in place (see above), checking
/// each offset and length against its buffer before a byte is read. Decoded accessors get the
/// decoded count, and min / max recomputed where the file had them (Draco quantisation moves
/// values slightly, and the glTF validator checks min / max exactly). Returns one note per
/// extension decoded, for the user; an empty list when the file used neither. Fails, naming the
/// primitive or buffer view, on a stream that does not decode or does not fit its accessors.
[[nodiscard]] Result<std::vector<std::string>> decode_compression(tinygltf::Model& model);

}  // namespace exao::gltf
