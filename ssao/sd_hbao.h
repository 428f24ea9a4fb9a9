#pragma once
// exao::ssao::sd_hbao: stochastic-depth HBAO (seed 000, Alg. 2). A step whose first-layer sample
// lies beyond r looks at the S stochastic depths of its pixel and keeps the one that would occlude
// most, W(|v|) (sin phi - sin h); a first-layer sample within r is used alone (their Sec. 3.3
// shortcut). No compensation factor (their Fig. 7 and 8 only).

#include <vector>

#include "ssao/horizon_march.h"
#include "ssao/stochastic_depth.h"

namespace exao::ssao {

/// AO per pixel, before any blur. `map` must be the view's size.
[[nodiscard]] std::vector<float> sd_hbao(const View& view, const StochasticDepth& map, const Settings& settings,
                                         const HbaoOptions& options);

}  // namespace exao::ssao
