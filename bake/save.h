#pragma once
// Writing a baked document: the glTF (.gltf with a .bin beside it or data: URIs as the input
// had, or one self-contained .glb), and each AO map as PNG and OpenEXR beside it. Every file goes
// through a temporary file and a rename (core/atomic_write.h), the glTF last, so it never
// refers to a file that is not there yet; no file of the input is ever written.

#include <string>
#include <vector>

#include "bake/result.h"
#include "bake/document.h"
#include "core/error.h"

namespace exao::bake {

struct SaveOptions {
  std::string path;   // OUT.gltf or OUT.glb (case-insensitive)
  int png_bits = 8;   // AO maps: 8 or 16 bits per texel
};

/// The files a save writes, for checks before a long bake: the glTF, its .bin (OUT.bin, when
/// .gltf and the input's buffers were not embedded), and per map OUT_ao[_label].png and .exr.
/// Fails when `path` has another extension, any of them is a file of the input, or png_bits is
/// neither 8 nor 16.
[[nodiscard]] Result<std::vector<std::string>> planned_outputs(const Document& document, const BakeResult* result,
                                                               const SaveOptions& options);

/// Writes everything; returns the files written, in order. Buffers are merged into one;
/// images the input had are kept as they were: in a .glb embedded (PNG and JPEG files found
/// beside the input, as buffer views), in a .gltf referenced by the same URI and copied beside
/// the output when it is in another folder. The AO maps are embedded in a .glb and referenced
/// by file name from a .gltf. Notes (a kept image that could not be copied...) go to `notes`.
[[nodiscard]] Result<std::vector<std::string>> save(const Document& document, const BakeResult& result,
                                                    const SaveOptions& options, std::vector<std::string>& notes);

}  // namespace exao::bake
