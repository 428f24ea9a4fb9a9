#pragma once
// Pictures of a comparison: AO as grey, the signed error against exact as a heat map, and a
// contact sheet that lays labelled cells (an AO tile over its heat map) in a grid.

#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace exao::ssao {

struct RgbImage {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgb;  // 3 bytes a pixel, row-major from the top-left
};

/// Grey AO (1 = white), dark blue-grey where no triangle is seen.
[[nodiscard]] RgbImage grey_image(std::span<const float> ao, std::span<const std::uint8_t> valid, int width, int height);

/// Signed error ao - exact: white where equal, toward blue where the method is lighter (missed
/// occlusion), toward red where it is darker, saturating at |error| = full_scale; dark
/// blue-grey where no triangle is seen.
[[nodiscard]] RgbImage heat_map(std::span<const float> ao, std::span<const float> exact,
                                std::span<const std::uint8_t> valid, int width, int height, double full_scale = 0.25);

/// A width x height key to heat_map: the error from -full_scale (left) to +full_scale (right),
/// labelled.
[[nodiscard]] RgbImage heat_map_legend(int width, int height, double full_scale = 0.25);

struct SheetCell {
  std::string label;               // above the cell
  const RgbImage* top = nullptr;   // AO
  const RgbImage* bottom = nullptr;  // heat map, or none
};

/// Cells in rows of `columns`, each tile shrunk by an integer factor (box filter) to at most
/// `tile_width` pixels wide; all tops the same size, likewise all bottoms.
[[nodiscard]] RgbImage contact_sheet(std::span<const SheetCell> cells, int columns, int tile_width);

}  // namespace exao::ssao
