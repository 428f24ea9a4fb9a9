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

std::vector<float> rt_svao_columns(const View& view, const VaoResult& phase1, const Settings& settings,
                                   const VaoOptions& options, const SegmentHits& hits) {
  std::vector<float> ao = phase1.ao;
  tbb::parallel_for(std::size_t{0}, view.pixel_count(), [&](std::size_t p) {
    const std::uint8_t flags = phase1.flags[p];
    if (flags == 0) return;
    const glm::dvec3 e = glm::normalize(view.eye - glm::dvec3(view.position[p]));
    std::vector<double> crossings;
    double sum = 0.0;
    for (int i = 0; i < kVaoSamples; ++i) {
      if (!((flags >> i) & 1u)) continue;
      const VaoSample s = vao_sample(view, settings, p, i);
      const auto q = static_cast<std::size_t>(s.pixel);  // flagged: on screen, a surface seen
      double u = unoccupied(s, surface_z(view, settings, p, s, q), options.thickness);  // a_i1, the depth buffer's
      // A surface changes a_i only between the end of the falloff area and the end of the
      // hemisphere part (Sec. 3.6): the ray covers exactly that stretch of the column.
      const double z_top = 1.0 + options.thickness + (s.z_hi - s.z_lo);
      const glm::dvec3 from = s.point + z_top * settings.radius * e, to = s.point + s.z_lo * settings.radius * e;
      crossings.clear();
      hits(from, to, crossings);
      for (const double f : crossings) u = std::min(u, unoccupied(s, z_top + f * (s.z_lo - z_top), options.thickness));
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
