#pragma once
// The order the engine visits receivers in: Morton (Z-curve) order of their positions, so that
// neighbouring receivers traverse alike and caches stay warm. The only copy in exao.

#include <cstdint>
#include <span>
#include <vector>

#include "core/receiver_frame.h"

namespace exao::engine {

/// A permutation of [0, receivers.size()): order[i] is the i-th receiver to visit. Positions are
/// quantised to 21 bits per axis over the receivers' bounding box. NaN-safe: a NaN or infinite
/// coordinate gets cell 0 on that axis (the result is still a permutation); ties keep the
/// input's order. Parallel (TBB) sort.
[[nodiscard]] std::vector<std::uint32_t> morton_order(std::span<const Receiver> receivers);

}  // namespace exao::engine
