#pragma once
// AO maps as greyscale PNG bytes, 8 or 16 bits: kept in memory so one encoding is both written
// beside the glTF and embedded in a .glb.

#include <cstdint>
#include <span>
#include <vector>

#include "core/error.h"

namespace exao::bake {

/// Checks the PNG depth of AO maps: 8 or 16; the error names the option "png_bits".
[[nodiscard]] Result<void> check_png_bits(int bits);

/// Encodes width x height values in [0, 1] (clamped; NaN as 0), row-major from the top row, as a
/// greyscale PNG of `bits` 8 or 16, rounded to the nearest level. Linear values (no gamma chunk):
/// glTF reads occlusion from the R channel as linear data.
[[nodiscard]] Result<std::vector<std::uint8_t>> encode_grey_png(std::span<const float> values, int width, int height,
                                                                int bits);

}  // namespace exao::bake
