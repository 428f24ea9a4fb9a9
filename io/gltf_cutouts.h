#pragma once
// exao::gltf::read_cutouts: the alpha-tested materials of a glTF model (alphaMode MASK, and
// BLEND for core/cutouts.h's policy) with their base colour textures' alpha decoded, and every
// scene triangle of theirs with its UVs (texCoord set, KHR_texture_transform) and COLOR_0 alpha;
// shared by the scene loader and the bake, so both see the same cut-outs. Internal: it exposes
// tinygltf (io/gltf_model.h).
//
// Bad input never fails the load; each case has a defined fallback and one note:
//  - an image that is missing, not PNG or JPEG, or does not decode: texture alpha 1 (the
//    material's alpha is baseColorFactor.a x COLOR_0.a, opaque unless they say otherwise);
//  - an image larger than kMaxCutoutTexels: the same (it is not decoded at all);
//  - a texCoord set (or COLOR_0) the primitive does not have, or that does not read: the
//    primitive's triangles are opaque;
//  - a corner with a NaN or infinite UV: that triangle is opaque.

#include <tiny_gltf.h>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "core/cutouts.h"
#include "io/gltf_walk.h"

namespace exao::gltf {

/// The largest texture a cut-out decodes: 8192 x 8192 texels (256 MiB as RGBA8, 128 MiB of
/// alpha kept). A card's alpha needs far less; a larger image is a mistake or an attack.
inline constexpr std::uint64_t kMaxCutoutTexels = std::uint64_t{1} << 26;

/// tinygltf's image callback that keeps each image's encoded bytes undecoded, in
/// `*static_cast<std::vector<std::vector<std::uint8_t>>*>(user)`, by image index (an image
/// whose file is missing stays empty). read_cutouts decodes only the ones it needs.
bool keep_image_bytes(tinygltf::Image* image, int index, std::string* err, std::string* warn, int width, int height,
                      const unsigned char* bytes, int size, void* user);

/// The width and height a PNG or JPEG stream declares in its header, without decoding it;
/// false for anything else or a truncated header.
[[nodiscard]] bool image_header_size(std::span<const std::uint8_t> bytes, std::uint32_t& width,
                                     std::uint32_t& height);

/// The model's cut-outs for the walk's scene triangles (nullptr when no triangle has a MASK or
/// BLEND material), with the default policy's rules (MASK cuts out, BLEND opaque); notes in
/// `notes` (see the file comment). `image_bytes[i]`: image i's encoded bytes (keep_image_bytes).
[[nodiscard]] std::shared_ptr<const Cutouts> read_cutouts(const ModelBytes& bytes, const ModelWalk& walk,
                                                          std::span<const std::vector<std::uint8_t>> image_bytes,
                                                          std::vector<std::string>& notes);

}  // namespace exao::gltf
