#pragma once
// A 5 x 7 pixel font of capitals, digits and a little punctuation, to label contact sheets
// without a font library. Lower case is drawn as upper case; unknown characters as blanks.

#include <cstdint>
#include <span>
#include <string_view>

namespace exao::ssao {

inline constexpr int kGlyphWidth = 5, kGlyphHeight = 7;

/// Draws `text` into an RGB image (width x height, 3 bytes a pixel) with its top-left corner at
/// (x, y), each font pixel a scale x scale block of `colour`; clipped to the image.
void draw_text(std::span<std::uint8_t> rgb, int width, int height, int x, int y, std::string_view text, int scale,
               const std::uint8_t colour[3]);

/// Width in pixels of `text` at `scale` (one blank column between glyphs).
[[nodiscard]] int text_width(std::string_view text, int scale);

}  // namespace exao::ssao
