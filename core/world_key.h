#pragma once
// A receiver key from where the receiver is, not from which pixel sees it (DESIGN.md section 3
// lets the caller choose keys). Two cameras that see the same surface point give it the same
// key, so the same rays: exact AO becomes view-independent, as a stereo pair needs (seed 003).

#include <cmath>
#include <cstdint>

#include <glm/glm.hpp>

#include "core/random.h"

namespace exao {

/// The hash of the cell of a grid of spacing `cell` (world units, > 0) that holds p. The grid is
/// shifted by 0.382 of a cell (1 - 1/golden ratio) so that the axis-aligned planes of modelled
/// scenes, at round coordinates, do not lie on cell boundaries, where float noise would split
/// one surface's receivers between two keys.
[[nodiscard]] inline std::uint64_t world_key(const glm::vec3& p, float cell) {
  constexpr double kShift = 0.3819660112501051;
  const auto q = [&](float v) {
    return static_cast<std::uint64_t>(static_cast<std::int64_t>(std::floor(static_cast<double>(v) / cell + kShift)));
  };
  return mix64(q(p.x) ^ mix64(q(p.y) ^ mix64(q(p.z) ^ 0x5eedull)));
}

}  // namespace exao
