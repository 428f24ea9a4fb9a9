#pragma once
// The screen-space walk that HBAO (Bavoil, Sainz, Dimitrov 2008) and its multi-layer variants
// share, as seed 000's Alg. 2 states it: N_d directions in screen space, rotated per pixel; N_s
// steps along each, of r' / (N_s + 1) pixels (r' the radius projected at the receiver's depth),
// the first one offset at random (the step layout of NVIDIA's HBAO+ shader: first sample at
// 1 + jitter * step pixels, then one step apart). Per direction d_i (lines 8-10) the tangent t_p
// is the surface's direction that projects onto d_i, t its angle with the view-space XY plane
// (the image plane), and the horizon starts at h = t + bias; a sample at v = s - p has the angle
// phi of v with the XY plane (line 14), a sample below the horizon is skipped (line 15), and one
// within r adds W(|v|) (sin phi - sin h) and raises h to phi (lines 18-19). On an open plane
// every sample lies along t_p, so phi = t < h and the plane is open.
//
// Angles::Tangent keeps the form exao had before (not the paper's): angles measured from the
// receiver's tangent plane (sin phi = n . v / |v|), so t = 0 and h starts at the bias, and the
// gain is f(sin phi) - f(sin h) with f the identity or, with `cosine`, the square (sin^2 h is
// the cosine-weighted share of a hemisphere below elevation h above the tangent plane, the
// weighting exao's rays have; it means nothing for angles from the XY plane, so check() allows
// it only with Angles::Tangent). The two differ: at t = 30 and phi = 60 degrees (from the XY
// plane) the slice's elevation above the tangent is 30 degrees, sin 30 = 0.50, where Alg. 2
// gains sin 60 - sin 30 = 0.37.
//
// A Layers policy says which depths a step sees beyond the G-buffer's first layer:
//   static constexpr bool kAllLayers: true  -> every step takes the best of layers(q) alone
//                                              (seed 004, Alg. 1: max over the fragment list);
//                                     false -> seed 000's Alg. 2: the first layer, and the
//                                              extra layers only when it is beyond r.
//   void layers(const View& view, std::size_t q, glm::dvec2 c, auto&& emit) calls
//   emit(point, opacity) for each depth of pixel q, as a point of the ray through c when it
//   knows the surface's plane (see below), else at q's centre.
//
// Samples are taken at the continuous screen point c of each step, as Alg. 2 walks them; the
// pixel q under c holds a surface point at its centre, up to 0.7 pixels off the slice. Alg. 2
// measures phi against the tangent t_p of the slice, so such an offset would change phi by the
// surface's slope across the slice: on an open floor seen at a grazing angle the first step's
// sample rises well above t + bias, and HBAO would darken open surfaces. The G-buffer's and the
// A-buffer's fragments carry their plane (the pixel's normal, the fragment's triangle), so
// the sample is that plane's point on the ray through c (View::point_on_plane): a plane's
// samples then lie on t_p exactly. GPU HBAO solves the same problem by snapping the step to
// texel centres and taking t_p along the snapped step (Bavoil et al.'s shader); exao's steps
// are not snapped, so its reconstruction is per sample. The stochastic depth map stores depths
// only: its samples stay at q's centre (they only matter where the first layer is beyond r).

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include <tbb/parallel_for.h>

#include "ssao/settings.h"
#include "ssao/view.h"

namespace exao::ssao {

enum class Angles {
  ViewPlane,  // seed 000's Alg. 2: from the view-space XY plane, gain W (sin phi - sin h), h0 = t + bias
  Tangent,    // from the receiver's tangent plane, t = 0 (exao's earlier form; see above)
};

struct HbaoOptions {
  int directions = 8;   // N_d: seeds 000 and 001 (Bavoil et al. use 8 directions x 4 steps)
  int steps = 4;        // N_s
  double bias = 0.1;    // radians added to the tangent angle, Alg. 2 line 10 (seed 000 leaves its
                        // value open: 0.1 rad, whose sine 0.0998 is HBAO+'s NdotV bias 0.1)
  Angles angles = Angles::ViewPlane;
  bool cosine = false;  // f(s) = s^2 instead of the papers' s; Angles::Tangent only
};

namespace detail {

/// The walk for one receiver: the point P with unit normal n, at view depth `depth`, seen at
/// pixel p (whose centre the walk starts from and whose 4 x 4 block cell gives the jitter).
/// horizon_march calls it with the G-buffer's receiver of every pixel; seed 004's transparent
/// receivers (ssao/abuffer_oit.h) with the deeper fragments of a pixel and either normal.
/// Returns AO in [0, 1].
template <class Layers>
[[nodiscard]] double march_receiver(const View& view, const Settings& settings, const HbaoOptions& o, const Layers& policy,
                                    std::size_t p, const glm::dvec3& P, const glm::dvec3& n, double depth) {
  const auto f = [&](double s) { return o.cosine ? s * s : s; };
  const double radius_px = settings.radius * view.pixels_per_unit(depth);
  if (radius_px < 1.0) return 1.0;  // the radius covers no neighbour: open, as HBAO+ does
  const double step = radius_px / (o.steps + 1);
  const glm::dvec2 centre = view.centre(p);
  const double rotation = block_jitter(p, view.width, 0), offset = block_jitter(p, view.width, 1);
  const bool tangent = o.angles == Angles::Tangent;
  // The axis angles are measured from: the receiver's normal, or the view-space Z axis (toward
  // the eye, perpendicular to the image plane).
  const glm::dvec3 axis = tangent ? n : -view.forward;
  const glm::dvec3 to_p = P - view.eye;
  double occlusion = 0.0;
  for (int d = 0; d < o.directions; ++d) {
    const double angle = 2.0 * std::numbers::pi * (d + rotation) / o.directions;
    const glm::dvec2 dir(std::cos(angle), std::sin(angle));
    double sin_h = std::sin(o.bias);
    if (!tangent) {
      // t_p: the tangent plane's line through P in the plane of the eye, P and the screen
      // direction (pixel y grows downward), oriented to move along d_i on screen.
      const glm::dvec3 screen = dir.x * view.right - dir.y * view.up;
      const glm::dvec3 across = glm::cross(to_p, screen);
      glm::dvec3 t_p = glm::cross(across, n);
      const glm::dvec3 along = screen - glm::dot(screen, to_p) / glm::dot(to_p, to_p) * to_p;
      if (glm::dot(t_p, along) < 0.0) t_p = -t_p;
      const double length = glm::length(t_p);
      if (!(length > 0.0)) continue;  // the surface is seen edge-on along d_i: no slice
      const double t = std::asin(std::clamp(glm::dot(t_p, axis) / length, -1.0, 1.0));
      // Past pi / 2 no sample can rise above the horizon: nothing to gain in this direction.
      sin_h = t + o.bias < 0.5 * std::numbers::pi ? std::sin(t + o.bias) : 1.0;
    }
    for (int s = 0; s < o.steps; ++s) {
      const double t = 1.0 + (offset + s) * step;
      const std::int64_t q = view.pixel_at(centre + t * dir);  // t: pixels from the centre
      if (q < 0) break;
      if (static_cast<std::size_t>(q) == p) continue;
      const auto sample = [&](const glm::dvec3& S, double& sin_phi) {
        const glm::dvec3 v = S - P;
        const double length = glm::length(v);
        sin_phi = length > 0.0 ? glm::dot(v, axis) / length : -1.0;
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
      const glm::dvec2 c = centre + t * dir;
      if constexpr (Layers::kAllLayers) {
        policy.layers(view, qi, c, consider);
      } else {
        if (!view.valid[qi]) continue;
        double sin_phi = 0.0;
        const double length =
            sample(view.point_on_plane(c, glm::dvec3(view.position[qi]), glm::dvec3(view.normal[qi])), sin_phi);
        if (sin_phi < sin_h) continue;  // Alg. 2 line 15
        if (length < settings.radius) {
          best = falloff_weight(settings, length) * (f(sin_phi) - f(sin_h));
          best_sin = sin_phi;
        } else {
          policy.layers(view, qi, c, consider);
        }
      }
      if (best > 0.0) {
        occlusion += best;
        sin_h = best_sin;
      }
    }
  }
  return std::clamp(1.0 - occlusion / o.directions, 0.0, 1.0);
}

template <class Layers>
[[nodiscard]] std::vector<float> horizon_march(const View& view, const Settings& settings, const HbaoOptions& o,
                                               const Layers& policy) {
  std::vector<float> ao(view.pixel_count(), 1.0f);
  tbb::parallel_for(std::size_t{0}, view.pixel_count(), [&](std::size_t p) {
    if (!view.valid[p]) return;
    ao[p] = static_cast<float>(march_receiver(view, settings, o, policy, p, glm::dvec3(view.position[p]),
                                              glm::dvec3(view.normal[p]), static_cast<double>(view.depth[p])));
  });
  return ao;
}

}  // namespace detail
}  // namespace exao::ssao
