#pragma once
// exao::gltf::glb_in_place: a GLB for tinygltf whose BIN chunk stops after the embedded images,
// so that the mesh bytes stay in the mapped file. tinygltf copies the whole BIN chunk into its
// Buffer (a resize that zeroes it, then a copy): for a 108 MB scan that copy, and the fresh pages
// it faults in, were most of the load (perf, docs/scale.md). The scene loader reads accessors
// from the file instead (ModelBytes, io/gltf_model.h); the bake, which writes the buffer back out,
// keeps tinygltf's copy. Internal to io/.

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

namespace exao::gltf {

struct GlbInPlace {
  std::vector<unsigned char> container;    // header, JSON (buffer 0's byteLength cut), short BIN chunk
  std::span<const unsigned char> buffer0;  // buffer 0's real bytes, in the caller's `glb`
};

/// The short container for `glb`, or nothing when the file does not qualify, and tinygltf reads it
/// whole as before: no BIN chunk, a buffer 0 with a URI, compression extensions (their decoders
/// rewrite buffers), JSON that does not parse, or an image view that is malformed or outside the
/// BIN chunk. Buffer 0 keeps the bytes the images use (at least one, as tinygltf wants).
[[nodiscard]] std::optional<GlbInPlace> glb_in_place(std::span<const unsigned char> glb);

}  // namespace exao::gltf
