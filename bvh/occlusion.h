#pragma once
// exao::bvh::occlusion: the BVH backend for a batch of receivers (paper Sec. 5), in parallel.

#include <span>

#include "bvh/bvh.h"
#include "bvh/traverse.h"
#include "core/mask_set.h"
#include "core/progress.h"
#include "core/receiver_frame.h"
#include "lut/mask_engine.h"

namespace exao::bvh {

/// Masks of `receivers`, in their order, by TBB tasks over consecutive receivers: give them in a
/// coherent order (engine/morton.h; nearby receivers traverse alike, so caches stay warm). With
/// `stats`, the work counters are summed into it.
[[nodiscard]] MaskSet occlusion(const Bvh& bvh, const lut::MaskEngine& engine, std::span<const Receiver> receivers,
                                const ProgressCallback& progress = {}, TraversalStats* stats = nullptr);

}  // namespace exao::bvh
