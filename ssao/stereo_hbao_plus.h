#pragma once
// exao::ssao::stereo_hbao_plus: stereo-aware HBAO+ obscurance (seed 003, Shi, Billeter, Eisemann
// 2022, Sec. 3.1-3.2), before its filter (ssao/stereo_filter.h).
//
// Sec. 3.1, the estimate: a pixel's samples lie on a world-space disc centred at its point P and
// facing the eyes' shared forward axis, at the distances of HBAO+'s steps (ssao/hbao_plus.h:
// N_d directions, N_s steps, the same per-pixel jitter), so in the pixel's own view they fall
// where mono HBAO+'s steps do. Each sample is projected into both views and HBAO+'s estimator
// W(|v|) max(n.v/|v| - bias, 0) is evaluated on the surface each view holds there; the two
// are averaged when both pixels are seen by both eyes (their Case A: L^l and L^r, reverse
// reprojection with back-check, both white), and the larger is kept otherwise (Case B: an
// occluder only one eye sees). A view whose pixel is off screen, holds no surface, or is the
// receiver's own pixel there contributes nothing (as mono HBAO+ skips its own pixel).
//
// Sec. 3.2, reprojection: the left eye is evaluated, and a right pixel that passes the
// back-check takes the left value of the left pixel it maps to (the nearest one: no
// interpolation, so no value is replicated across a disocclusion); the others, the holes, are
// evaluated from scratch with the same stereo estimate, from the right eye.
//
// Both views must be of the same size and of parallel cameras (ssao::stereo_cameras): the disc
// faces the shared forward axis and the right and up axes are shared.

#include <cstdint>
#include <vector>

#include "ssao/hbao_plus.h"
#include "ssao/settings.h"
#include "ssao/view.h"

namespace exao::ssao {

/// The pixel of `other` nearest to the projection of world point P (-1 off screen or behind).
[[nodiscard]] std::int64_t nearest_pixel(const View& other, const glm::dvec3& P);

/// Seed 003's L^v: per pixel of `view`, 1 when its point is seen by `other` too (the nearest
/// pixel there sees a surface whose point projects back within one pixel of this pixel's centre).
[[nodiscard]] std::vector<std::uint8_t> seen_by_both(const View& view, const View& other);

struct StereoObscurance {
  std::vector<float> left, right;          // AO per pixel (1 where no triangle is seen), before any filter
  std::vector<std::uint8_t> left_both, right_both;  // L^l, L^r
  std::size_t reprojected = 0;             // right pixels that took a left value
  std::size_t holes = 0;                   // right pixels evaluated from scratch
};

/// The stereo estimate of pixel p of `view` (the other eye `other`; `both`, `other_both` their
/// L textures). AO in [0, 1].
[[nodiscard]] double stereo_estimate(const View& view, const View& other, const std::vector<std::uint8_t>& both,
                                     const std::vector<std::uint8_t>& other_both, std::size_t p, const Settings& settings,
                                     const HbaoPlusOptions& options);

/// Sec. 3.1-3.2 for a stereo pair: the left eye evaluated, reprojected to the right, the holes filled.
[[nodiscard]] StereoObscurance stereo_hbao_plus(const View& left, const View& right, const Settings& settings,
                                                const HbaoPlusOptions& options);

}  // namespace exao::ssao
