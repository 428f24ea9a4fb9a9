#include "lut/brute.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "core/bounds.h"
#include "lut/float_mode.h"

namespace exao::lut {
namespace {

// A uniform grid where each cell lists the triangles whose influence sphere (centre, radius + r)
// overlaps it, by bounding box. A query is then one cell: the one that holds the ray origin.
class InfluenceGrid {
 public:
  InfluenceGrid(const TriangleSet& triangles, float ray_radius) {
    const std::size_t n = triangles.size();
    reach_.resize(n);
    Bounds bounds;
    for (std::size_t t = 0; t < n; ++t) {
      // triangle_mask rejects when |centre - origin| > radius + r, computed in float in the
      // receiver frame (relative error a few 1e-7): 1e-5 relative covers that.
      reach_[t] = (triangles.radius[t] + ray_radius) * (1.0f + 1e-5f);
      bounds.extend(triangles.centre[t] - reach_[t]);
      bounds.extend(triangles.centre[t] + reach_[t]);
    }
    if (n == 0 || bounds.empty()) return;
    const glm::vec3 extent = bounds.extent();
    // Cells of 2r hold about twice the true candidates; at most 128 per axis keeps the index small.
    cell_ = std::max(2.0f * ray_radius, std::max(extent.x, std::max(extent.y, extent.z)) / 128.0f);
    for (;;) {
      if (fill(triangles, bounds)) break;
      cell_ *= 2.0f;  // too many entries (huge triangles against a small r): coarser cells
    }
  }

  [[nodiscard]] std::span<const std::uint32_t> candidates(const glm::vec3& p) const {
    if (items_.empty()) return {};
    int i[3];
    for (int k = 0; k < 3; ++k) {
      const float x = std::floor((p[k] - lo_[k]) / cell_);
      if (!(x >= 0.0f && x < static_cast<float>(size_[k]))) return {};  // also NaN
      i[k] = static_cast<int>(x);
    }
    const std::size_t c = index(i[0], i[1], i[2]);
    return {items_.data() + start_[c], items_.data() + start_[c + 1]};
  }

 private:
  [[nodiscard]] std::size_t index(int x, int y, int z) const {
    return (static_cast<std::size_t>(z) * static_cast<std::size_t>(size_[1]) + static_cast<std::size_t>(y)) *
               static_cast<std::size_t>(size_[0]) + static_cast<std::size_t>(x);
  }

  // The cell range of triangle t, grown by a thousandth of a cell on each side: a query point
  // within rounding of a cell boundary may land in either cell.
  void range(const TriangleSet& triangles, std::size_t t, int lo[3], int hi[3]) const {
    const float pad = 1e-3f * cell_;
    for (int k = 0; k < 3; ++k) {
      const float a = (triangles.centre[t][k] - reach_[t] - pad - lo_[k]) / cell_;
      const float b = (triangles.centre[t][k] + reach_[t] + pad - lo_[k]) / cell_;
      lo[k] = std::clamp(static_cast<int>(std::floor(a)), 0, size_[k] - 1);
      hi[k] = std::clamp(static_cast<int>(std::floor(b)), 0, size_[k] - 1);
    }
  }

  // Counts, then fills, the cell lists (each in increasing triangle order). False when the lists
  // would exceed kMaxEntries.
  bool fill(const TriangleSet& triangles, const Bounds& bounds) {
    constexpr std::size_t kMaxEntries = std::size_t{1} << 26;
    lo_ = bounds.lo;
    for (int k = 0; k < 3; ++k) size_[k] = std::max(1, static_cast<int>(std::ceil(bounds.extent()[k] / cell_)));
    const std::size_t cells = static_cast<std::size_t>(size_[0]) * static_cast<std::size_t>(size_[1]) *
                              static_cast<std::size_t>(size_[2]);
    std::vector<std::uint32_t> count(cells + 1, 0);
    std::size_t total = 0;
    int lo[3], hi[3];
    for (std::size_t t = 0; t < triangles.size(); ++t) {
      range(triangles, t, lo, hi);
      total += static_cast<std::size_t>(hi[0] - lo[0] + 1) * static_cast<std::size_t>(hi[1] - lo[1] + 1) *
               static_cast<std::size_t>(hi[2] - lo[2] + 1);
      if (total > kMaxEntries) return false;
      for (int z = lo[2]; z <= hi[2]; ++z)
        for (int y = lo[1]; y <= hi[1]; ++y)
          for (int x = lo[0]; x <= hi[0]; ++x) ++count[index(x, y, z)];
    }
    start_.assign(cells + 1, 0);
    for (std::size_t c = 0; c < cells; ++c) start_[c + 1] = start_[c] + count[c];
    items_.resize(total);
    std::vector<std::uint32_t> next(start_.begin(), start_.end() - 1);
    for (std::size_t t = 0; t < triangles.size(); ++t) {
      range(triangles, t, lo, hi);
      for (int z = lo[2]; z <= hi[2]; ++z)
        for (int y = lo[1]; y <= hi[1]; ++y)
          for (int x = lo[0]; x <= hi[0]; ++x) items_[next[index(x, y, z)]++] = static_cast<std::uint32_t>(t);
    }
    return true;
  }

  std::vector<float> reach_;
  glm::vec3 lo_{0.0f};
  float cell_ = 1.0f;
  int size_[3] = {0, 0, 0};
  std::vector<std::uint32_t> start_;  // cell c lists items_[start_[c], start_[c + 1])
  std::vector<std::uint32_t> items_;
};

template <class Candidates>
MaskSet occlusion(const MaskEngine& engine, const TriangleSet& triangles, std::span<const Receiver> receivers,
                  const ProgressCallback& progress, Candidates&& candidates) {
  MaskSet masks(receivers.size(), engine.samples());
  ProgressCounter counter(progress, receivers.size());
  with_mask_bits(engine.samples(), [&](auto bits) {
    constexpr int Bits = decltype(bits)::value;
    const Mask<Bits> all = engine.all_rays<Bits>();
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, receivers.size(), 16),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                        const FlushDenormals flush;
                        for (std::size_t r = range.begin(); r != range.end(); ++r) {
                          const Frame frame = engine.rays().frame(receivers[r]);
                          Mask<Bits> mask;
                          for (const std::uint32_t t : candidates(frame.origin)) {
                            if (!triangles.blocks_for(t, frame)) continue;  // the excluded object
                            mask |= engine.triangle_mask<Bits>(triangles, t, frame);
                            if (mask == all) break;  // nothing left to block: more ORs change nothing
                          }
                          store(mask, masks.row(r));
                        }
                        counter.add(range.size());
                      });
  });
  return masks;
}

}  // namespace

MaskSet brute_occlusion(const MaskEngine& engine, const TriangleSet& triangles, std::span<const Receiver> receivers,
                        const ProgressCallback& progress) {
  const InfluenceGrid grid(triangles, engine.rays().radius);
  return occlusion(engine, triangles, receivers, progress, [&](const glm::vec3& p) { return grid.candidates(p); });
}

MaskSet brute_occlusion_every_triangle(const MaskEngine& engine, const TriangleSet& triangles,
                                       std::span<const Receiver> receivers) {
  std::vector<std::uint32_t> every(triangles.size());
  for (std::size_t t = 0; t < every.size(); ++t) every[t] = static_cast<std::uint32_t>(t);
  return occlusion(engine, triangles, receivers, {},
                   [&](const glm::vec3&) { return std::span<const std::uint32_t>(every); });
}

}  // namespace exao::lut
