#pragma once
// exao::ssao::hbao: horizon-based AO (Bavoil, Sainz, Dimitrov 2008) on the G-buffer's single
// depth layer, as seed 000 states it (Eq. 3, Alg. 2 without the stochastic branch).

#include <vector>

#include "core/error.h"
#include "ssao/horizon_march.h"

namespace exao::ssao {

/// directions and steps in 1 .. 64, bias in [0, 1).
[[nodiscard]] Result<void> check(const HbaoOptions& options);

/// AO per pixel (1 open, 0 occluded; 1 where no triangle is seen), before any blur.
[[nodiscard]] std::vector<float> hbao(const View& view, const Settings& settings, const HbaoOptions& options);

}  // namespace exao::ssao
