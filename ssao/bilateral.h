#pragma once
// exao::ssao::bilateral_blur: the depth-aware separable blur every screen-space method of the
// seeds ends with (seed 001 Sec. 3.4: radius 4, HBAO+'s filter), as NVIDIA's public HBAO+ blur
// (Blur_Common.hlsl, CrossBilateralWeight) weighs a pixel k pixels away: exp2(-k^2 / (2 sigma^2)
// - dz^2), sigma = (R + 1) / 2, dz the view-depth difference to the centre pixel times the
// sharpness; horizontal, then vertical; depth only, no normal test. The sharpness is exao's
// choice, 4 / r (r the AO radius: pixels about a quarter radius apart in depth are different
// surfaces), where HBAO+ takes a user constant in view-depth units; its optional depth-slope
// correction is not applied. Pixels without a triangle are neither read nor written.

#include <vector>

#include "ssao/view.h"

namespace exao::ssao {

/// Blurs `ao` (one value per pixel of `view`) in place; radius 0 leaves it unchanged.
void bilateral_blur(const View& view, double ao_radius, int radius, std::vector<float>& ao);

}  // namespace exao::ssao
