#pragma once
// exao::ssao: stochastic-depth HBAO+ and its multi-view form (seed 000, Vermeer, Scandolo,
// Eisemann 2021; Sec. 3.2 "we simply include all stochastic samples in the HBAO+ calculation",
// Sec. 3.4 and Alg. 3). Per camera l (Alg. 3, ComputeAO): the receiver P is projected into l,
// the steps of HBAO+ (ssao/hbao_plus.h: N_d directions, N_s steps of r' / (N_s + 1), the same
// per-pixel jitter) are walked in l's image, and at every step the samples of l's stochastic
// depth map at that pixel (its centre, at each stored depth) are tried and the largest
// W(|v|) max(n.v/|v| - bias, 0) is kept (lines 18-25). The main camera also has its G-buffer
// (the conventional depth map, Sec. 3.3), whose sample is tried with them. Over the cameras
// the larger sum is kept (line 5), and AO = 1 - 2 sum / ((1 - bias) N_d N_s), NVIDIA's scale as
// in mono HBAO+ (Alg. 3 line 6 writes 1 - sum / (N_d N_s)), so that with only the first layer it
// is HBAO+. A step landing on P's own pixel in l is skipped, as mono HBAO+ skips its own pixel.
//
// The secondary camera (Sec. 3.4: "at a set distance to the side of the original camera, and
// angled such that the original camera frustum is fully covered"): the main eye turned by an
// angle about the main camera's up axis through the centroid of the points the main view sees,
// looking at that centroid, with the narrowest field of view that holds every one of those
// points (plus 2%), and the main image's size. Its depths are a stochastic depth map drawn from
// its own A-buffer, so what is hidden from it is still sampled.

#include <optional>
#include <vector>

#include "core/camera.h"
#include "core/error.h"
#include "ssao/hbao_plus.h"
#include "ssao/settings.h"
#include "ssao/stochastic_depth.h"
#include "ssao/view.h"

namespace exao::ssao {

struct MultiViewOptions {
  double angle_degrees = 45.0;  // the secondary eye's turn about the main camera's up axis, (-180, 180), not 0
};

[[nodiscard]] Result<void> check(const MultiViewOptions& options);

/// The secondary camera for `main` (which must see at least one triangle), as described above.
[[nodiscard]] Camera secondary_camera(const View& main, const MultiViewOptions& options);

/// One camera's depths for Alg. 3: its projection (view_basis) and stochastic depth map of the
/// same size.
struct DepthCamera {
  View projection;
  const StochasticDepth* map = nullptr;
};

/// SD-HBAO+ on the main view alone: its G-buffer and its stochastic depth map. AO per pixel,
/// before any blur.
[[nodiscard]] std::vector<float> sd_hbao_plus(const View& view, const StochasticDepth& map, const Settings& settings,
                                              const HbaoPlusOptions& options);

/// Alg. 3: the main view (G-buffer and `map`) and the secondary cameras. AO per pixel, before
/// any blur.
[[nodiscard]] std::vector<float> multiview_sd_hbao_plus(const View& view, const StochasticDepth& map,
                                                        const std::vector<DepthCamera>& secondary, const Settings& settings,
                                                        const HbaoPlusOptions& options);

}  // namespace exao::ssao
