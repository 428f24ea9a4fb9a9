#include "ssao/svao.h"

#include <algorithm>
#include <cassert>

#include <tbb/parallel_for.h>

namespace exao::ssao {

std::vector<float> sd_svao(const View& view, const VaoResult& phase1, const StochasticDepth& map,
                           const Settings& settings, const VaoOptions& options) {
  std::vector<float> ao = phase1.ao;
  tbb::parallel_for(std::size_t{0}, view.pixel_count(), [&](std::size_t p) {
    const std::uint8_t flags = phase1.flags[p];
    if (flags == 0) return;
    double sum = 0.0;
    for (int i = 0; i < kVaoSamples; ++i) {
      if (!((flags >> i) & 1u)) continue;
      const VaoSample s = vao_sample(view, settings, p, i);
      const auto q = static_cast<std::size_t>(s.pixel);  // flagged: on screen, a surface seen
      // The first layer as phase 1 read it; the stochastic depths, which carry no plane, at q's centre.
      double u = unoccupied(s, surface_z(view, settings, p, s, q), options.thickness);
      for (const float w : map.at(q)) {
        if (w == kNoDepth) continue;
        u = std::min(u, unoccupied(s, column_z(view, settings, p, view.point_at(q, w)), options.thickness));
      }
      sum += u / s.height;
    }
    ao[p] = static_cast<float>(static_cast<double>(phase1.unflagged[p]) + 2.0 * sum / kVaoSamples);
  });
  return ao;
}

std::vector<std::uint32_t> flagged_pixels(const VaoResult& phase1) {
  std::vector<std::uint32_t> out;
  for (std::size_t p = 0; p < phase1.flags.size(); ++p) {
    if (phase1.flags[p]) out.push_back(static_cast<std::uint32_t>(p));
  }
  return out;
}

std::vector<float> rt_svao(const VaoResult& phase1, std::span<const float> exact) {
  std::vector<float> ao = phase1.ao;
  const std::vector<std::uint32_t> pixels = flagged_pixels(phase1);
  assert(pixels.size() == exact.size());
  for (std::size_t k = 0; k < pixels.size(); ++k) ao[pixels[k]] = exact[k];
  return ao;
}

}  // namespace exao::ssao
