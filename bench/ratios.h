#pragma once
// The figures of `exao bench` that compare rows of one (N, r): speed, the speed-up over the first
// (Embree's reference) row, how each row's masks agree with the reference's ray for ray, and a
// raster+lod row's own error and speed-up against raster without a level of detail.

#include <cstddef>
#include <span>

#include "bench/plan.h"
#include "bench/report.h"
#include "core/mask_set.h"

namespace exao::bench {

/// Fills Run::ray_agreement, identical_receivers, mean_abs_error, max_abs_error, bias and
/// identical_8bit of `run`: `masks` against `reference` (the same receivers, in order, N rays).
/// With no receivers: full agreement and no error.
void add_agreement(const MaskSet& reference, const MaskSet& masks, Run& run);

/// Every row's ratios: `runs[c]` timed `configs[c]` with masks `results[c]` on `receivers`
/// receivers, row 0 the reference. Fills mrays_per_s, speedup_vs_embree, the agreement with row 0
/// (add_agreement), and for raster+lod rows the lod_*_vs_raster figures against the raster row of
/// the same mask mode and instruction set. Every run's seconds must be > 0; the spans equal in size.
void add_ratios(std::span<Run> runs, std::span<const MaskSet> results, std::span<const Config> configs,
                std::size_t receivers);

}  // namespace exao::bench
