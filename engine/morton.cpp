#include "engine/morton.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include <tbb/parallel_sort.h>

#include "core/bounds.h"
#include "core/check.h"

namespace exao::engine {
namespace {

constexpr float kLastCell = 2097151.0f;  // 2^21 - 1: three axes fill 63 bits

// Spreads the low 21 bits of x to every third bit (one axis of a Morton code).
std::uint64_t spread_bits(std::uint64_t x) {
  x &= 0x1FFFFF;
  x = (x | x << 32) & 0x1F00000000FFFFull;
  x = (x | x << 16) & 0x1F0000FF0000FFull;
  x = (x | x << 8) & 0x100F00F00F00F00Full;
  x = (x | x << 4) & 0x10C30C30C30C30C3ull;
  x = (x | x << 2) & 0x1249249249249249ull;
  return x;
}

// The cell of a coordinate already scaled to [0, kLastCell]. A NaN fails `q >= 0` and lands in
// cell 0, where casting it to an integer would be undefined.
std::uint64_t cell(float q) { return q >= 0.0f ? static_cast<std::uint64_t>(std::min(q, kLastCell)) : 0; }

bool finite(const glm::vec3& p) { return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z); }

}  // namespace

std::vector<std::uint32_t> morton_order(std::span<const Receiver> receivers) {
  EXAO_CHECK_LE(receivers.size(), std::size_t{0xFFFFFFFFu});
  Bounds bounds;
  for (const Receiver& r : receivers) {
    if (finite(r.position)) bounds.extend(r.position);  // one NaN must not void the box
  }
  const glm::vec3 scale = glm::vec3(kLastCell) / glm::max(bounds.extent(), glm::vec3(1e-30f));
  std::vector<std::pair<std::uint64_t, std::uint32_t>> keyed(receivers.size());
  for (std::size_t i = 0; i < receivers.size(); ++i) {
    const glm::vec3 q = (receivers[i].position - bounds.lo) * scale;
    keyed[i] = {spread_bits(cell(q.x)) | spread_bits(cell(q.y)) << 1 | spread_bits(cell(q.z)) << 2,
                static_cast<std::uint32_t>(i)};
  }
  tbb::parallel_sort(keyed.begin(), keyed.end());
  std::vector<std::uint32_t> order(receivers.size());
  for (std::size_t i = 0; i < keyed.size(); ++i) order[i] = keyed[i].second;
  return order;
}

}  // namespace exao::engine
