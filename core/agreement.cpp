#include "core/agreement.h"

#include <algorithm>
#include <bit>
#include <cassert>
#include <cmath>
#include <cstdint>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/combinable.h>
#include <tbb/parallel_for.h>

namespace exao {

Agreement& Agreement::operator+=(const Agreement& o) {
  receivers += o.receivers;
  rays += o.rays;
  rays_differ += o.rays_differ;
  identical_ao += o.identical_ao;
  receivers_differ += o.receivers_differ;
  classified = classified || o.classified;
  rays_differ_grazing += o.rays_differ_grazing;
  receivers_grazing += o.receivers_grazing;
  ao_differ_not_grazing += o.ao_differ_not_grazing;
  largest_closeness = std::max(largest_closeness, o.largest_closeness);
  ao += o.ao;
  return *this;
}

Agreement compare_masks(const MaskSet& reference, const MaskSet& masks, std::span<const Receiver> receivers,
                        const ShadowRays& rays, const GrazingTest* grazing) {
  assert(reference.size() == masks.size() && reference.size() == receivers.size());
  assert(reference.samples() == masks.samples());
  tbb::combinable<Agreement> parts;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, reference.size(), 256), [&](const auto& range) {
    Agreement& a = parts.local();
    std::vector<int> differing;
    for (std::size_t r = range.begin(); r != range.end(); ++r) {
      differing.clear();
      for (int w = 0; w < reference.words(); ++w) {
        std::uint64_t x = reference.row(r)[static_cast<std::size_t>(w)] ^ masks.row(r)[static_cast<std::size_t>(w)];
        while (x) {
          differing.push_back(64 * w + std::countr_zero(x));
          x &= x - 1;
        }
      }
      ++a.receivers;
      a.rays += static_cast<std::size_t>(reference.samples());
      a.rays_differ += differing.size();
      const bool same_ao = reference.blocked_count(r) == masks.blocked_count(r);
      a.identical_ao += same_ao;
      a.ao.add(masks.ao(r), reference.ao(r));
      if (differing.empty()) continue;
      ++a.receivers_differ;
      if (!grazing) continue;
      const std::vector<double> closeness = grazing->closeness(rays.frame(receivers[r]), differing);
      std::size_t grazing_rays = 0;
      for (const double c : closeness) {
        if (c <= kGrazingUlps) {
          ++grazing_rays;
          a.largest_closeness = std::max(a.largest_closeness, c);
        }
      }
      a.rays_differ_grazing += grazing_rays;
      if (grazing_rays == differing.size()) {
        ++a.receivers_grazing;
      } else if (!same_ao) {
        ++a.ao_differ_not_grazing;
      }
    }
  });
  Agreement total;
  parts.combine_each([&](const Agreement& a) { total += a; });
  total.classified = grazing != nullptr;
  return total;
}

}  // namespace exao
