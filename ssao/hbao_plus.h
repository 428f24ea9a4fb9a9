#pragma once
// exao::ssao::hbao_plus: HBAO+ (NVIDIA 2013-2016; seed 000 Sec. 3.2, seed 003), as NVIDIA's
// open shader computes it: the same directions and steps as HBAO, but no horizon; each sample
// within r adds W(|v|) max(n.v / |v| - bias, 0), the sum is scaled by 1 / (1 - bias) and by
// 1 / (N_d N_s), and AO = clamp(1 - 2 sum, 0, 1). W is exao's falloff (ssao/settings.h) in place
// of NVIDIA's 1 - |v|^2 / r^2.

#include <vector>

#include "core/error.h"
#include "ssao/settings.h"
#include "ssao/view.h"

namespace exao::ssao {

struct HbaoPlusOptions {
  int directions = 8;   // NVIDIA's NUM_DIRECTIONS (seed 003 uses 10)
  int steps = 4;        // NUM_STEPS
  double bias = 0.1;    // NdotV bias, [0, 1)
};

[[nodiscard]] Result<void> check(const HbaoPlusOptions& options);

/// AO per pixel (1 where no triangle is seen), before any blur.
[[nodiscard]] std::vector<float> hbao_plus(const View& view, const Settings& settings, const HbaoPlusOptions& options);

}  // namespace exao::ssao
