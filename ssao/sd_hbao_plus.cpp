#include "ssao/sd_hbao_plus.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <numbers>
#include <string>

#include <tbb/parallel_for.h>

namespace exao::ssao {
namespace {

// Alg. 3's ComputeAO for camera `l`: the sum over directions and steps of the best sample.
// `gbuffer` is the main view when l is the main camera (its first layer is tried too).
double compute_ao(const View& l, const StochasticDepth& map, const View* gbuffer, std::size_t p, int width,
                  const glm::dvec3& P, const glm::dvec3& n, const Settings& settings, const HbaoPlusOptions& o) {
  // In the main view the walk starts at the pixel's centre, as mono HBAO+'s does.
  const double depth = gbuffer ? static_cast<double>(gbuffer->depth[p]) : glm::dot(P - l.eye, l.forward);
  if (!(depth > 0.0)) return 0.0;
  const glm::dvec2 centre = gbuffer ? l.centre(p) : l.project(P);
  const std::int64_t own = gbuffer ? static_cast<std::int64_t>(p) : l.pixel_at(centre);
  const double radius_px = settings.radius * l.pixels_per_unit(depth);
  if (radius_px < 1.0) return 0.0;
  const double step = radius_px / (o.steps + 1);
  const double rotation = block_jitter(p, width, 0), offset = block_jitter(p, width, 1);
  double sum = 0.0;
  const auto estimate = [&](const glm::dvec3& S) {
    const glm::dvec3 v = S - P;
    const double length = glm::length(v);
    return length > 0.0 ? falloff_weight(settings, length) * std::max(glm::dot(n, v) / length - o.bias, 0.0) : 0.0;
  };
  for (int d = 0; d < o.directions; ++d) {
    const double angle = 2.0 * std::numbers::pi * (d + rotation) / o.directions;
    const glm::dvec2 dir(std::cos(angle), std::sin(angle));
    for (int s = 0; s < o.steps; ++s) {
      const std::int64_t q = l.pixel_at(centre + (1.0 + (offset + s) * step) * dir);
      if (q < 0) break;
      if (q == own) continue;
      const auto qi = static_cast<std::size_t>(q);
      double best = 0.0;
      if (gbuffer && gbuffer->valid[qi]) best = estimate(glm::dvec3(gbuffer->position[qi]));
      for (const float w : map.at(qi)) {
        if (w != kNoDepth) best = std::max(best, estimate(l.point_at(qi, static_cast<double>(w))));
      }
      sum += best;
    }
  }
  return sum;
}

}  // namespace

Result<void> check(const MultiViewOptions& options) {
  if (!(std::abs(options.angle_degrees) > 0.0 && std::abs(options.angle_degrees) < 180.0)) {
    return fail("secondary view angle: must be in (-180, 180) degrees and not 0, got " + std::to_string(options.angle_degrees));
  }
  return {};
}

Camera secondary_camera(const View& main, const MultiViewOptions& options) {
  glm::dvec3 pivot(0.0);
  std::size_t seen = 0;
  for (std::size_t p = 0; p < main.pixel_count(); ++p) {
    if (!main.valid[p]) continue;
    pivot += glm::dvec3(main.position[p]);
    ++seen;
  }
  assert(seen > 0);
  pivot /= static_cast<double>(seen);
  // Rodrigues' rotation of the eye about the up axis through the pivot; a positive angle moves
  // the eye toward the main camera's right.
  const glm::dvec3 k = glm::normalize(main.up);
  const glm::dvec3 d = main.eye - pivot;
  const double a = glm::radians(options.angle_degrees);
  const glm::dvec3 turned = d * std::cos(a) + glm::cross(k, d) * std::sin(a) + k * glm::dot(k, d) * (1.0 - std::cos(a));
  const glm::dvec3 eye = pivot + turned;
  const glm::dvec3 forward = glm::normalize(pivot - eye);
  glm::dvec3 up = k - glm::dot(k, forward) * forward;
  up = glm::length(up) > 1e-6 ? glm::normalize(up) : glm::normalize(main.forward - glm::dot(main.forward, forward) * forward);
  const glm::dvec3 right = glm::cross(forward, up);
  // The narrowest field of view that holds every point the main view sees.
  double tan_needed = 1e-3;
  for (std::size_t p = 0; p < main.pixel_count(); ++p) {
    if (!main.valid[p]) continue;
    const glm::dvec3 v = glm::dvec3(main.position[p]) - eye;
    const double w = glm::dot(v, forward);
    if (!(w > 1e-9)) continue;  // behind the secondary eye: it cannot hold it at any angle
    tan_needed = std::max({tan_needed, std::abs(glm::dot(v, up)) / w, std::abs(glm::dot(v, right)) / (w * main.aspect)});
  }
  Camera c;
  c.name = main.camera.name + "-secondary";
  c.eye = glm::vec3(eye);
  c.forward = glm::vec3(forward);
  c.up = glm::vec3(up);
  c.yfov = static_cast<float>(std::min(2.0 * std::atan(1.02 * tan_needed), glm::radians(170.0)));
  return c;
}

std::vector<float> sd_hbao_plus(const View& view, const StochasticDepth& map, const Settings& settings,
                                const HbaoPlusOptions& options) {
  return multiview_sd_hbao_plus(view, map, {}, settings, options);
}

std::vector<float> multiview_sd_hbao_plus(const View& view, const StochasticDepth& map, const std::vector<DepthCamera>& secondary,
                                          const Settings& settings, const HbaoPlusOptions& o) {
  assert(map.width == view.width && map.height == view.height);
  std::vector<float> ao(view.pixel_count(), 1.0f);
  tbb::parallel_for(std::size_t{0}, view.pixel_count(), [&](std::size_t p) {
    if (!view.valid[p]) return;
    const glm::dvec3 P(view.position[p]);
    const glm::dvec3 n(view.normal[p]);
    // Mono HBAO+'s guard: a radius below a pixel in the main view is open.
    if (settings.radius * view.pixels_per_unit(view.depth[p]) < 1.0) return;
    double sum = compute_ao(view, map, &view, p, view.width, P, n, settings, o);
    for (const DepthCamera& c : secondary) {
      sum = std::max(sum, compute_ao(c.projection, *c.map, nullptr, p, view.width, P, n, settings, o));  // Alg. 3 line 5
    }
    sum *= 1.0 / ((1.0 - o.bias) * o.directions * o.steps);
    ao[p] = static_cast<float>(std::clamp(1.0 - 2.0 * sum, 0.0, 1.0));
  });
  return ao;
}

}  // namespace exao::ssao
