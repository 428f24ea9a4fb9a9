#pragma once
// exao::ssao::stereo_filter: seed 003's stereo-aware bilateral filter (Shi, Billeter, Eisemann
// 2022, Sec. 3.3, Fig. 6). For pixel p of either eye, with world point P, and p* the pixel of
// the other eye nearest to P's projection, each is filtered in its own image over its own
// N x N neighbourhood with P as the centre:
//   F(p^v) = sum_k O(k) G(|P - K|) / W(p^v),   W(p^v) = sum_k G(|P - K|),
// G a Gaussian of world distance with sigma = l / 3, l the world length that N pixels cover at
// P's depth (the paper's sigma = r / 3; its per-scene clamp [sigma_min, sigma_max] is not
// applied). The two are blended by which neighbourhood lies closer to P (their Fig. 6 D):
//   A(p) = w F(p) + (1 - w) F(p*),  w = smoothstep(0.5 - eta, 0.5, alpha),
//   alpha = W(p) / (W(p) + W(p*)),  eta = 0.05,
// so a pixel whose own samples are closer keeps its own filter (alpha >= 0.5: w = 1), and its
// counterpart, for which alpha is then below 1/2, takes the same value from this eye: both eyes
// end with one value. A p* off screen or on no surface gives w = 1. Form::Full is the N x N
// filter; Form::Separable the paper's fast form (their Fig. 7, ~3x faster): a horizontal pass of
// N pixels combined across the eyes as above, then a vertical pass over its output. N = 2R + 1
// for the blur radius R the other methods use (ssao/bilateral.h; R = 0: no filter). The two
// views must be of the same size, of parallel eyes; pixels without a triangle are left alone.

#include <vector>

#include "ssao/view.h"

namespace exao::ssao {

enum class StereoFilterForm { Full, Separable };

struct StereoFilterOptions {
  int radius = 4;                                  // R: N = 2R + 1 pixels (seed 003 uses 13: R = 6)
  double eta = 0.05;                               // Fig. 6 D
  StereoFilterForm form = StereoFilterForm::Separable;
};

/// Fig. 6 D's weight w of the own filter, for alpha = W(p) / (W(p) + W(p*)).
[[nodiscard]] double stereo_filter_weight(double alpha, double eta);

/// Filters both eyes' obscurance in place.
void stereo_filter(const View& left, const View& right, std::vector<float>& left_ao, std::vector<float>& right_ao,
                   const StereoFilterOptions& options);

}  // namespace exao::ssao
