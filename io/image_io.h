#pragma once
// Writing AO images: OpenEXR for the float values, PNG for a preview. Both atomically.

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "core/error.h"

namespace exao {

/// A width x height image, row-major from the top-left pixel.
struct AoImage {
  int width = 0;
  int height = 0;
  std::vector<float> ao;                // 1 = open, 0 = occluded; background pixels hold 1
  std::vector<float> coverage;          // 1 where a receiver is, 0 for background
  std::vector<std::uint32_t> blocked;   // blocked-ray count per pixel (optional: may be empty)
};

/// OpenEXR, 32-bit float channels: "Y" (AO) and "A" (coverage), plus "blocked" (UINT) when the
/// image carries counts.
[[nodiscard]] Result<void> write_exr(const AoImage& image, const std::string& path);

/// 8-bit grey + alpha PNG: grey = AO (linear, like a glTF occlusion map), alpha = coverage.
[[nodiscard]] Result<void> write_png(const AoImage& image, const std::string& path);

/// 8-bit grey or RGB PNG of raw bytes (channels 1 or 3), for plots and texture previews.
[[nodiscard]] Result<void> write_png_bytes(std::span<const std::uint8_t> pixels, int width, int height,
                                           int channels, const std::string& path);

}  // namespace exao
