#include "bench/ratios.h"

#include <bit>

#include "core/ao_error.h"
#include "core/check.h"

namespace exao::bench {

void add_agreement(const MaskSet& reference, const MaskSet& masks, Run& run) {
  std::uint64_t agree = 0;
  std::size_t identical = 0;
  const std::uint64_t rays = static_cast<std::uint64_t>(reference.size()) * static_cast<std::uint64_t>(reference.samples());
  for (std::size_t i = 0; i < reference.size(); ++i) {
    const auto a = reference.row(i);
    const auto b = masks.row(i);
    int differ = 0;
    for (std::size_t w = 0; w < a.size(); ++w) differ += std::popcount(a[w] ^ b[w]);
    agree += static_cast<std::uint64_t>(reference.samples() - differ);
    identical += reference.blocked_count(i) == masks.blocked_count(i);
  }
  const AoError error = ao_error(reference, masks);
  run.ray_agreement = rays ? static_cast<double>(agree) / static_cast<double>(rays) : 1.0;
  run.identical_receivers = reference.size() ? static_cast<double>(identical) / static_cast<double>(reference.size()) : 1.0;
  run.mean_abs_error = error.mean_abs();
  run.max_abs_error = error.max_abs;
  run.bias = error.bias();
  run.identical_8bit = error.identical_8bit_share();
}

void add_ratios(std::span<Run> runs, std::span<const MaskSet> results, std::span<const Config> configs,
                std::size_t receivers) {
  EXAO_CHECK_EQ(runs.size(), results.size());
  EXAO_CHECK_EQ(runs.size(), configs.size());
  for (std::size_t c = 0; c < configs.size(); ++c) {
    Run& run = runs[c];
    run.mrays_per_s = static_cast<double>(receivers) * run.samples / run.seconds * 1e-6;
    run.speedup_vs_embree = runs[0].seconds / run.seconds;
    add_agreement(results[0], results[c], run);
    if (configs[c].lod < 0) continue;
    // LOD's own error: against raster without LOD, same masks and instruction set.
    for (std::size_t b = 0; b < configs.size(); ++b) {
      if (configs[b].method != engine::Method::Raster || configs[b].lod >= 0 || configs[b].mode != configs[c].mode ||
          configs[b].isa != configs[c].isa) {
        continue;
      }
      const AoError own = ao_error(results[b], results[c]);
      run.lod_speedup_vs_raster = runs[b].seconds / run.seconds;
      run.lod_mean_abs_vs_raster = own.mean_abs();
      run.lod_max_abs_vs_raster = own.max_abs;
      run.lod_bias_vs_raster = own.bias();
      run.lod_identical_8bit_vs_raster = own.identical_8bit_share();
    }
  }
}

}  // namespace exao::bench
