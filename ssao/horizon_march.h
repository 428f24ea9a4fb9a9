#pragma once
// The screen-space walk that HBAO (Bavoil, Sainz, Dimitrov 2008) and its multi-layer variants
// share: N_d directions in screen space, rotated per pixel; N_s steps along each, of
// r' / (N_s + 1) pixels (r' the radius projected at the receiver's depth), the first one offset
// at random; per direction, the horizon rises to every sample within r above it, and the
// occlusion gained is W(|v|) (f(sin phi) - f(sin h)) (seed 000, Eq. 3, Alg. 2). f is the
// identity in the papers (the uniform-solid-angle obscurance, 1 - sin h per slice), or the
// square for cosine weighting as exao's rays have (sin^2 h is the cosine-weighted share of a
// hemisphere below elevation h). Angles are measured from the receiver's tangent plane, so the
// tangent angle t of Alg. 2 is 0 and its bias is the starting horizon. The step layout follows
// NVIDIA's HBAO+ shader: first sample at 1 + jitter * step pixels, then one step apart.
//
// A Layers policy says which depths a step sees beyond the G-buffer's first layer:
//   static constexpr bool kAllLayers: true  -> every step takes the best of layers(q) alone
//                                              (seed 004, Alg. 1: max over the fragment list);
//                                     false -> seed 000's Alg. 2: the first layer, and the
//                                              extra layers only when it is beyond r.
//   void layers(std::size_t q, auto&& emit) calls emit(view_depth, opacity) for each depth.

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include <tbb/parallel_for.h>

#include "ssao/settings.h"
#include "ssao/view.h"

namespace exao::ssao {

struct HbaoOptions {
  int directions = 8;   // N_d: seeds 000 and 001 (Bavoil et al. use 8 directions x 4 steps)
  int steps = 4;        // N_s
  double bias = 0.1;    // sine of the starting horizon above the tangent plane (HBAO+'s default
                        // NdotV bias; seed 000 leaves HBAO's angle bias open)
  bool cosine = false;  // f(s) = s^2 instead of the papers' s
};

namespace detail {

template <class Layers>
[[nodiscard]] std::vector<float> horizon_march(const View& view, const Settings& settings, const HbaoOptions& o,
                                               const Layers& policy) {
  std::vector<float> ao(view.pixel_count(), 1.0f);
  const auto f = [&](double s) { return o.cosine ? s * s : s; };
  tbb::parallel_for(std::size_t{0}, view.pixel_count(), [&](std::size_t p) {
    if (!view.valid[p]) return;
    const glm::dvec3 P(view.position[p]);
    const glm::dvec3 n(view.normal[p]);
    const double radius_px = settings.radius * view.pixels_per_unit(view.depth[p]);
    if (radius_px < 1.0) return;  // the radius covers no neighbour: open, as HBAO+ does
    const double step = radius_px / (o.steps + 1);
    const glm::dvec2 centre = view.centre(p);
    const double rotation = block_jitter(p, view.width, 0), offset = block_jitter(p, view.width, 1);
    double occlusion = 0.0;
    for (int d = 0; d < o.directions; ++d) {
      const double angle = 2.0 * std::numbers::pi * (d + rotation) / o.directions;
      const glm::dvec2 dir(std::cos(angle), std::sin(angle));
      double sin_h = o.bias;
      for (int s = 0; s < o.steps; ++s) {
        const double t = 1.0 + (offset + s) * step;
        const std::int64_t q = view.pixel_at(centre + t * dir);
        if (q < 0) break;
        if (static_cast<std::size_t>(q) == p) continue;
        const auto sample = [&](const glm::dvec3& S, double& sin_phi) {
          const glm::dvec3 v = S - P;
          const double length = glm::length(v);
          sin_phi = length > 0.0 ? glm::dot(v, n) / length : -1.0;
          return length;
        };
        double best = 0.0, best_sin = sin_h;
        const auto consider = [&](const glm::dvec3& S, double opacity) {
          double sin_phi = 0.0;
          const double length = sample(S, sin_phi);
          if (!(sin_phi > sin_h) || !(length < settings.radius)) return;
          const double gain = opacity * falloff_weight(settings, length) * (f(sin_phi) - f(sin_h));
          if (gain > best) {
            best = gain;
            best_sin = sin_phi;
          }
        };
        const auto qi = static_cast<std::size_t>(q);
        if constexpr (Layers::kAllLayers) {
          policy.layers(qi, [&](double w, double opacity) { consider(view.point_at(qi, w), opacity); });
        } else {
          if (!view.valid[qi]) continue;
          double sin_phi = 0.0;
          const double length = sample(glm::dvec3(view.position[qi]), sin_phi);
          if (sin_phi < sin_h) continue;  // Alg. 2 line 15
          if (length < settings.radius) {
            best = falloff_weight(settings, length) * (f(sin_phi) - f(sin_h));
            best_sin = sin_phi;
          } else {
            policy.layers(qi, [&](double w, double opacity) { consider(view.point_at(qi, w), opacity); });
          }
        }
        if (best > 0.0) {
          occlusion += best;
          sin_h = best_sin;
        }
      }
    }
    ao[p] = static_cast<float>(std::clamp(1.0 - occlusion / o.directions, 0.0, 1.0));
  });
  return ao;
}

}  // namespace detail
}  // namespace exao::ssao
