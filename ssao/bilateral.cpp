#include "ssao/bilateral.h"

#include <cmath>

#include <tbb/parallel_for.h>

namespace exao::ssao {

void bilateral_blur(const View& view, double ao_radius, int radius, std::vector<float>& ao) {
  if (radius <= 0) return;
  // HBAO+'s CrossBilateralWeight: exp2(-k^2 / (2 sigma^2) - dz^2), sigma = (R + 1) / 2.
  const double sigma = 0.5 * (radius + 1);
  const double falloff = 1.0 / (2.0 * sigma * sigma);
  const double sharpness = 4.0 / ao_radius;
  std::vector<float> temp(ao.size());
  const auto pass = [&](const std::vector<float>& in, std::vector<float>& out, int dx, int dy) {
    tbb::parallel_for(0, view.height, [&](int y) {
      for (int x = 0; x < view.width; ++x) {
        const std::size_t p = static_cast<std::size_t>(y) * static_cast<std::size_t>(view.width) + static_cast<std::size_t>(x);
        out[p] = in[p];
        if (!view.valid[p]) continue;
        double sum = 0.0, weight = 0.0;
        for (int k = -radius; k <= radius; ++k) {
          const int xs = x + k * dx, ys = y + k * dy;
          if (xs < 0 || ys < 0 || xs >= view.width || ys >= view.height) continue;
          const std::size_t q = static_cast<std::size_t>(ys) * static_cast<std::size_t>(view.width) + static_cast<std::size_t>(xs);
          if (!view.valid[q]) continue;
          const double dz = (static_cast<double>(view.depth[q]) - view.depth[p]) * sharpness;
          const double w = std::exp2(-k * k * falloff - dz * dz);
          sum += w * in[q];
          weight += w;
        }
        out[p] = static_cast<float>(sum / weight);
      }
    });
  };
  pass(ao, temp, 1, 0);
  pass(temp, ao, 0, 1);
}

}  // namespace exao::ssao
