#include "ssao/stochastic_depth.h"

#include <bit>
#include <cmath>
#include <cstring>
#include <string>

#include <tbb/parallel_for.h>

#include "core/random.h"

namespace exao::ssao {

Result<void> check(const StochasticDepthOptions& options) {
  if (options.samples < 1 || options.samples > 16) {
    return fail("stochastic depth samples: must be from 1 to 16, got " + std::to_string(options.samples));
  }
  if (!(options.alpha > 0.0 && options.alpha <= 1.0)) {
    return fail("stochastic depth alpha: must be in (0, 1], got " + std::to_string(options.alpha));
  }
  return {};
}

std::vector<std::vector<std::uint32_t>> subset_table(int samples) {
  std::vector<std::vector<std::uint32_t>> table(static_cast<std::size_t>(samples) + 1);
  for (std::uint32_t mask = 0; mask < (1u << samples); ++mask) {
    table[static_cast<std::size_t>(std::popcount(mask))].push_back(mask);
  }
  return table;
}

StochasticDepth make_stochastic_depth(const FragmentBuffer& fragments, const StochasticDepthOptions& options,
                                      std::span<const std::uint8_t> stencil) {
  StochasticDepth map;
  map.width = fragments.width;
  map.height = fragments.height;
  map.samples = options.samples;
  const std::size_t pixels = static_cast<std::size_t>(map.width) * static_cast<std::size_t>(map.height);
  map.depth.assign(pixels * static_cast<std::size_t>(options.samples), kNoDepth);
  const auto table = subset_table(options.samples);
  const double expected = options.alpha * options.samples;
  tbb::parallel_for(std::size_t{0}, pixels, [&](std::size_t p) {
    if (!stencil.empty() && stencil[p] == 0) return;
    float* out = map.depth.data() + p * static_cast<std::size_t>(options.samples);
    for (const Fragment& f : fragments.at(p)) {
      std::uint32_t depth_bits = 0;
      std::memcpy(&depth_bits, &f.depth, sizeof depth_bits);
      const std::uint64_t h = mix64(options.seed ^ mix64(p * 0x9E3779B97F4A7C15ull ^ mix64((std::uint64_t{f.triangle} << 32) | depth_bits)));
      // Alg. 1, Eq. 1: R = floor(alpha S + xi).
      const int r = std::min(options.samples, static_cast<int>(std::floor(expected + unit_double(h))));
      if (r == 0) continue;
      const auto& masks = table[static_cast<std::size_t>(r)];
      const std::uint32_t mask = masks[static_cast<std::size_t>(Rng(h).below(static_cast<std::uint32_t>(masks.size())))];
      for (int j = 0; j < options.samples; ++j) {
        if ((mask >> j) & 1u) out[j] = std::min(out[j], f.depth);
      }
    }
  });
  return map;
}

}  // namespace exao::ssao
