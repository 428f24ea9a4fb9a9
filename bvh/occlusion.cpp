#include "bvh/occlusion.h"

#include <algorithm>
#include <numeric>

#include <tbb/blocked_range.h>
#include <tbb/combinable.h>
#include <tbb/parallel_for.h>

#include "lut/float_mode.h"

namespace exao::bvh {
namespace {

template <int Bits, bool Stats>
void run(const Bvh& bvh, const lut::MaskEngine& engine, std::span<const Receiver> receivers,
         MaskSet& masks, const ProgressCallback& progress,
         TraversalStats* stats) {
  ProgressCounter counter(progress, receivers.size());
  tbb::combinable<TraversalStats> local;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, receivers.size(), 64), [&](const tbb::blocked_range<std::size_t>& range) {
    const lut::FlushDenormals flush;  // the same float mode as every other backend
    TraversalStats& mine = local.local();
    OccluderCache cache;  // neighbours in the range share occluders
    for (std::size_t r = range.begin(); r < range.end(); ++r) {
      const Frame frame = engine.rays().frame(receivers[r]);
      store(traverse<Bits, Stats>(bvh, engine, frame, &mine, &cache), masks.row(r));
    }
    counter.add(range.size());
  });
  if (stats) local.combine_each([&](const TraversalStats& s) { *stats += s; });
}

}  // namespace

MaskSet occlusion(const Bvh& bvh, const lut::MaskEngine& engine, std::span<const Receiver> receivers,
                  const ProgressCallback& progress, TraversalStats* stats) {
  MaskSet masks(receivers.size(), engine.samples());
  with_mask_bits(engine.samples(), [&](auto bits) {
    constexpr int Bits = decltype(bits)::value;
    if (stats) {
      run<Bits, true>(bvh, engine, receivers, masks, progress, stats);
    } else {
      run<Bits, false>(bvh, engine, receivers, masks, progress, nullptr);
    }
  });
  return masks;
}

}  // namespace exao::bvh
