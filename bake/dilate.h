#pragma once
// The dilation margin of an AO map: texels next to a chart take the values of the chart's
// border, so that bilinear filtering and mipmaps near a chart's edge read AO, not the empty
// background (which would show as seams).

#include <cstdint>
#include <span>

namespace exao::bake {

/// Grows the filled texels (filled[i] != 0) of a width x height map by `margin` rings: in each
/// ring, every empty texel with a filled 8-neighbour takes their mean and becomes filled (with
/// state 2). Texels still empty afterwards get `background`. `values` and `filled` have
/// width * height entries, row-major.
void dilate(std::span<float> values, std::span<std::uint8_t> filled, int width, int height, int margin,
            float background);

}  // namespace exao::bake
