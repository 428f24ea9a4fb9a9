#include "ssao/stereo_hbao_plus.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <numbers>

#include <tbb/parallel_for.h>

namespace exao::ssao {

std::int64_t nearest_pixel(const View& other, const glm::dvec3& P) { return other.pixel_at(other.project(P)); }

std::vector<std::uint8_t> seen_by_both(const View& view, const View& other) {
  std::vector<std::uint8_t> both(view.pixel_count(), 0);
  tbb::parallel_for(std::size_t{0}, view.pixel_count(), [&](std::size_t p) {
    if (!view.valid[p]) return;
    const std::int64_t q = nearest_pixel(other, glm::dvec3(view.position[p]));
    if (q < 0 || !other.valid[static_cast<std::size_t>(q)]) return;
    // The back-check (their Fig. 5 d): within one pixel width.
    const glm::dvec2 back = view.project(glm::dvec3(other.position[static_cast<std::size_t>(q)]));
    both[p] = glm::length(back - view.centre(p)) <= 1.0 ? 1 : 0;
  });
  return both;
}

double stereo_estimate(const View& view, const View& other, const std::vector<std::uint8_t>& both,
                       const std::vector<std::uint8_t>& other_both, std::size_t p, const Settings& settings,
                       const HbaoPlusOptions& o) {
  const glm::dvec3 P(view.position[p]);
  const glm::dvec3 n(view.normal[p]);
  const double ppu = view.pixels_per_unit(view.depth[p]);
  const double radius_px = settings.radius * ppu;
  if (radius_px < 1.0) return 1.0;  // mono HBAO+'s guard
  const double step = radius_px / (o.steps + 1);
  const double rotation = block_jitter(p, view.width, 0), offset = block_jitter(p, view.width, 1);
  const std::int64_t own_other = nearest_pixel(other, P);
  // HBAO+'s estimator on the surface view `v` holds at its pixel q (q != own), and whether q is
  // seen by both eyes. Returns false when there is no surface to read.
  const auto contribution = [&](const View& v, const std::vector<std::uint8_t>& seen, std::int64_t q, std::int64_t own,
                                double& value, bool& in_both) {
    if (q < 0 || q == own || !v.valid[static_cast<std::size_t>(q)]) return false;
    const auto qi = static_cast<std::size_t>(q);
    const glm::dvec3 d = glm::dvec3(v.position[qi]) - P;
    const double length = glm::length(d);
    value = length > 0.0 ? falloff_weight(settings, length) * std::max(glm::dot(n, d) / length - o.bias, 0.0) : 0.0;
    in_both = seen[qi] != 0;
    return true;
  };
  double sum = 0.0;
  for (int d = 0; d < o.directions; ++d) {
    const double angle = 2.0 * std::numbers::pi * (d + rotation) / o.directions;
    // The disc faces the shared forward axis; screen y grows downward.
    const glm::dvec3 along = std::cos(angle) * view.right - std::sin(angle) * view.up;
    for (int s = 0; s < o.steps; ++s) {
      const glm::dvec3 S = P + ((1.0 + (offset + s) * step) / ppu) * along;
      double a = 0.0, b = 0.0;
      bool a_both = false, b_both = false;
      const bool has_a = contribution(view, both, nearest_pixel(view, S), static_cast<std::int64_t>(p), a, a_both);
      const bool has_b = contribution(other, other_both, nearest_pixel(other, S), own_other, b, b_both);
      if (has_a && has_b && a_both && b_both) {
        sum += 0.5 * (a + b);  // Case A: both eyes see the sampled surface
      } else {
        sum += std::max(has_a ? a : 0.0, has_b ? b : 0.0);  // Case B: one eye's occluder counts
      }
    }
  }
  sum *= 1.0 / ((1.0 - o.bias) * o.directions * o.steps);
  return std::clamp(1.0 - 2.0 * sum, 0.0, 1.0);
}

StereoObscurance stereo_hbao_plus(const View& left, const View& right, const Settings& settings, const HbaoPlusOptions& o) {
  assert(left.width == right.width && left.height == right.height);
  StereoObscurance out;
  out.left_both = seen_by_both(left, right);
  out.right_both = seen_by_both(right, left);
  out.left.assign(left.pixel_count(), 1.0f);
  out.right.assign(right.pixel_count(), 1.0f);
  tbb::parallel_for(std::size_t{0}, left.pixel_count(), [&](std::size_t p) {
    if (left.valid[p]) out.left[p] = static_cast<float>(stereo_estimate(left, right, out.left_both, out.right_both, p, settings, o));
  });
  std::vector<std::uint8_t> hole(right.pixel_count(), 0);
  tbb::parallel_for(std::size_t{0}, right.pixel_count(), [&](std::size_t q) {
    if (!right.valid[q]) return;
    if (out.right_both[q]) {
      const std::int64_t p = nearest_pixel(left, glm::dvec3(right.position[q]));  // passed the back-check: on screen, valid
      out.right[q] = out.left[static_cast<std::size_t>(p)];
    } else {
      hole[q] = 1;
      out.right[q] = static_cast<float>(stereo_estimate(right, left, out.right_both, out.left_both, q, settings, o));
    }
  });
  for (std::size_t q = 0; q < right.pixel_count(); ++q) {
    if (!right.valid[q]) continue;
    if (hole[q]) ++out.holes;
    else ++out.reprojected;
  }
  return out;
}

}  // namespace exao::ssao
