#pragma once
// exao::ssao::bilateral_blur: the depth-aware separable blur every screen-space method of the
// seeds ends with (seed 001 Sec. 3.4: radius 4, HBAO+'s filter). Gaussian of sigma = (R + 1) / 2
// pixels across, times exp(-(dz / (r / 4))^2) for the view-depth difference dz to the centre
// pixel (r the AO radius: pixels more than about a quarter radius apart in depth are different
// surfaces) and zero across surfaces whose normals differ by more than ~25 degrees; horizontal,
// then vertical. Pixels without a triangle are neither read nor written.

#include <vector>

#include "ssao/view.h"

namespace exao::ssao {

/// Blurs `ao` (one value per pixel of `view`) in place; radius 0 leaves it unchanged.
void bilateral_blur(const View& view, double ao_radius, int radius, std::vector<float>& ao);

}  // namespace exao::ssao
