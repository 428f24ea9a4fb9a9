#pragma once
// exao::gltf::read_file: a .gltf or .glb file into a tinygltf Model, for the scene loader and the
// bake alike. Internal: it exposes tinygltf (io/gltf_model.h).

#include <tiny_gltf.h>

#include <exception>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "core/error.h"
#include "io/gltf_model.h"
#include "io/mapped_file.h"

namespace exao::gltf {

/// Where a GLB's BIN chunk goes: into the model's buffer 0 (the bake, which writes the model back
/// out), or nowhere, its accessors read in place from the mapped file (the scene loader; see
/// io/glb_in_place.h). A file that does not qualify is read whole either way.
enum class BinChunk { Copied, InPlace };

/// A glTF file as read: its model with any Draco or meshopt compression already decoded
/// (io/gltf_compression.h), and what the file was before decoding merged its buffers.
struct File {
  tinygltf::Model model;
  bool binary = false;                    // a GLB container
  std::vector<std::string> buffer_uris;   // per buffer of the file as written (empty: GLB's BIN chunk)
  std::vector<std::string> notes;         // one line per compression extension decoded
  // With BinChunk::InPlace: the mapped file, and buffer 0's bytes in it (model.buffers[0].data
  // then holds only what the embedded images use).
  std::shared_ptr<const MappedFile> mapped;
  std::span<const unsigned char> buffer0_in_place;

  /// The model with its buffers' bytes, wherever they are: what every accessor read takes.
  [[nodiscard]] ModelBytes bytes() const { return {model, buffer0_in_place}; }
};

/// Reads `path`, told a .glb by its magic bytes rather than its name (a mislabelled file still
/// loads), and decodes its compressed geometry, so that every reader (the scene loader, the
/// bake) sees an ordinary model; `images` decides what happens to each image's bytes
/// (tinygltf's image callback, with `user`). Fails with one line, without the file name (the
/// caller adds it): no such file, tinygltf's own message, or a stream that does not decode. May
/// throw what tinygltf throws (bad_alloc, json errors).
[[nodiscard]] Result<File> read_file(const std::string& path, tinygltf::LoadImageDataFunction images, void* user,
                                     BinChunk bin = BinChunk::Copied);

/// Whether the file starts with the GLB magic "glTF".
[[nodiscard]] bool is_glb(const std::string& path);

/// body() -> Result<T>, with any exception tinygltf or the standard library throws (bad_alloc on
/// a hostile count, json errors) turned into an error: none leaves a glTF reader. An error's
/// message gets the file name in front.
template <class T, class Body>
[[nodiscard]] Result<T> read_guarded(const std::string& path, Body&& body) {
  Result<T> out = fail("unknown error while reading glTF");
  try {
    out = body();
  } catch (const std::exception& e) {
    out = fail(one_line(e.what()));
  } catch (...) {
    out = fail("unknown error while reading glTF");
  }
  if (!out) return fail(path + ": " + out.error().message);
  return out;
}

}  // namespace exao::gltf
