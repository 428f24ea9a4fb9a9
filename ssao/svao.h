#pragma once
// exao::ssao: the stenciled two-phase VAO of seed 001. Phase 1 is ssao::vao on the depth buffer,
// which flags every sample whose surface lies in front of the constant area and marks, in the
// stochastic depth mask, the pixel that sample reads. Phase 2 revisits only the flagged pixels:
//  * SD-SVAO (their Sec. 3.9): a stochastic depth map drawn for the marked pixels only (the
//    stencil), and each flagged sample's unoccupied length is the least over the first layer
//    and every stochastic depth of its pixel, a_i = min(a_i1, ..., a_ij) (Sec. 3.6-3.7).
//  * RT-SVAO (Sec. 3.8): rays for the flagged pixels. Here the rays are exao's own: a flagged
//    pixel takes the exact AO of its receiver (the caller computes it for those pixels only), an
//    unflagged one keeps phase 1's value, so RT-SVAO's error is VAO's error where nothing was
//    flagged.

#include <span>
#include <vector>

#include "ssao/stochastic_depth.h"
#include "ssao/vao.h"

namespace exao::ssao {

/// SD-SVAO's phase 2. `map` is the stochastic depth map drawn with phase1.stencil.
[[nodiscard]] std::vector<float> sd_svao(const View& view, const VaoResult& phase1, const StochasticDepth& map,
                                         const Settings& settings, const VaoOptions& options);

/// Pixels phase 1 flagged (any bit set), in pixel order.
[[nodiscard]] std::vector<std::uint32_t> flagged_pixels(const VaoResult& phase1);

/// RT-SVAO: phase 1's AO, with exact[k] at flagged_pixels(phase1)[k].
[[nodiscard]] std::vector<float> rt_svao(const VaoResult& phase1, std::span<const float> exact);

}  // namespace exao::ssao
