#include "bvh/occlusion.h"

#include <algorithm>
#include <numeric>

#include <tbb/blocked_range.h>
#include <tbb/combinable.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include "core/bounds.h"
#include "lut/float_mode.h"

namespace exao::bvh {
namespace {

// Spreads the low 21 bits of x to every third bit.
std::uint64_t spread_bits(std::uint64_t x) {
  x &= 0x1FFFFF;
  x = (x | x << 32) & 0x1F00000000FFFFull;
  x = (x | x << 16) & 0x1F0000FF0000FFull;
  x = (x | x << 8) & 0x100F00F00F00F00Full;
  x = (x | x << 4) & 0x10C30C30C30C30C3ull;
  x = (x | x << 2) & 0x1249249249249249ull;
  return x;
}

std::vector<std::uint32_t> morton_order(std::span<const Receiver> receivers) {
  Bounds bounds;
  for (const Receiver& r : receivers) bounds.extend(r.position);
  const glm::vec3 scale = glm::vec3(2097151.0f) / glm::max(bounds.extent(), glm::vec3(1e-30f));
  std::vector<std::pair<std::uint64_t, std::uint32_t>> keyed(receivers.size());
  for (std::size_t i = 0; i < receivers.size(); ++i) {
    const glm::vec3 q = glm::clamp((receivers[i].position - bounds.lo) * scale, glm::vec3(0.0f), glm::vec3(2097151.0f));
    const std::uint64_t code = spread_bits(static_cast<std::uint64_t>(q.x)) |
                               spread_bits(static_cast<std::uint64_t>(q.y)) << 1 |
                               spread_bits(static_cast<std::uint64_t>(q.z)) << 2;
    keyed[i] = {code, static_cast<std::uint32_t>(i)};
  }
  tbb::parallel_sort(keyed.begin(), keyed.end());
  std::vector<std::uint32_t> order(receivers.size());
  for (std::size_t i = 0; i < keyed.size(); ++i) order[i] = keyed[i].second;
  return order;
}

template <int Bits, bool Stats>
void run(const Bvh& bvh, const lut::MaskEngine& engine, std::span<const Receiver> receivers,
         const std::vector<std::uint32_t>& order, MaskSet& masks, const ProgressCallback& progress,
         TraversalStats* stats) {
  ProgressCounter counter(progress, receivers.size());
  tbb::combinable<TraversalStats> local;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, order.size(), 64), [&](const tbb::blocked_range<std::size_t>& range) {
    const lut::FlushDenormals flush;  // the same float mode as every other backend
    TraversalStats& mine = local.local();
    for (std::size_t i = range.begin(); i < range.end(); ++i) {
      const std::uint32_t r = order[i];
      const Frame frame = engine.rays().frame(receivers[r]);
      store(traverse<Bits, Stats>(bvh, engine, frame, &mine), masks.row(r));
    }
    counter.add(range.size());
  });
  if (stats) local.combine_each([&](const TraversalStats& s) { *stats += s; });
}

}  // namespace

MaskSet occlusion(const Bvh& bvh, const lut::MaskEngine& engine, std::span<const Receiver> receivers,
                  const ProgressCallback& progress, TraversalStats* stats) {
  MaskSet masks(receivers.size(), engine.samples());
  const std::vector<std::uint32_t> order = morton_order(receivers);
  with_mask_bits(engine.samples(), [&](auto bits) {
    constexpr int Bits = decltype(bits)::value;
    if (stats) {
      run<Bits, true>(bvh, engine, receivers, order, masks, progress, stats);
    } else {
      run<Bits, false>(bvh, engine, receivers, order, masks, progress, nullptr);
    }
  });
  return masks;
}

}  // namespace exao::bvh
