#include "ssao/hbao_plus.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include <tbb/parallel_for.h>

namespace exao::ssao {

Result<void> check(const HbaoPlusOptions& options) {
  if (options.directions < 1 || options.directions > 64) return fail("directions: must be from 1 to 64, got " + std::to_string(options.directions));
  if (options.steps < 1 || options.steps > 64) return fail("steps: must be from 1 to 64, got " + std::to_string(options.steps));
  if (!(options.bias >= 0.0 && options.bias < 1.0)) return fail("bias: must be in [0, 1), got " + std::to_string(options.bias));
  return {};
}

std::vector<float> hbao_plus(const View& view, const Settings& settings, const HbaoPlusOptions& o) {
  std::vector<float> ao(view.pixel_count(), 1.0f);
  tbb::parallel_for(std::size_t{0}, view.pixel_count(), [&](std::size_t p) {
    if (!view.valid[p]) return;
    const glm::dvec3 P(view.position[p]);
    const glm::dvec3 n(view.normal[p]);
    const double radius_px = settings.radius * view.pixels_per_unit(view.depth[p]);
    if (radius_px < 1.0) return;
    const double step = radius_px / (o.steps + 1);
    const glm::dvec2 centre = view.centre(p);
    const double rotation = block_jitter(p, view.width, 0), offset = block_jitter(p, view.width, 1);
    double sum = 0.0;
    for (int d = 0; d < o.directions; ++d) {
      const double angle = 2.0 * std::numbers::pi * (d + rotation) / o.directions;
      const glm::dvec2 dir(std::cos(angle), std::sin(angle));
      for (int s = 0; s < o.steps; ++s) {
        const std::int64_t q = view.pixel_at(centre + (1.0 + (offset + s) * step) * dir);
        if (q < 0) break;
        const auto qi = static_cast<std::size_t>(q);
        if (qi == p || !view.valid[qi]) continue;
        const glm::dvec3 v = glm::dvec3(view.position[qi]) - P;
        const double length = glm::length(v);
        if (!(length > 0.0)) continue;
        sum += falloff_weight(settings, length) * std::max(glm::dot(n, v) / length - o.bias, 0.0);
      }
    }
    sum *= 1.0 / ((1.0 - o.bias) * o.directions * o.steps);
    ao[p] = static_cast<float>(std::clamp(1.0 - 2.0 * sum, 0.0, 1.0));
  });
  return ao;
}

}  // namespace exao::ssao
