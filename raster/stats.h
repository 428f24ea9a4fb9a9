#pragma once
// exao::raster::RasterStats: work counters of the raster backend, enough to print the paper's
// Table 2 (how many fragments reach each culling stage, and how many masks are computed).

#include <cstdint>
#include <string>

namespace exao::raster {

struct RasterStats {
  // Always counted.
  std::uint64_t receivers = 0;         // pixels that see a triangle
  std::uint64_t triangles = 0;         // triangles given
  std::uint64_t prisms = 0;            // volumes built as hexagonal prisms (Fig. 2)
  std::uint64_t billboards = 0;        // ... as billboards (Fig. 3)
  std::uint64_t boxes = 0;             // ... as boxes (degenerate triangles without a billboard)
  std::uint64_t volumes_off = 0;       // volumes drawn into no tile: off screen, or (without stats)
                                       // every receiver of their tiles is out of reach
  std::uint64_t tile_volumes = 0;      // (tile, volume) pairs drawn (some row of the tile in reach)
  std::uint64_t sphere_mask_skipped = 0;  // passed the tests, but the sphere's mask adds no ray
  std::uint64_t masks = 0;             // triangle_mask calls
  std::uint64_t masks_nonempty = 0;    // ... that set at least one bit

  // Counted only with RasterOptions::stats (and then the tile-level culls are off, so the
  // counts are exactly the paper's per-fragment ones). Table 2's "#frag" of row k is the
  // number of masks computed with tests 1..k on, so row "depth test only" is depth_passed and
  // the last row horizon_passed.
  std::uint64_t fragments = 0;         // far-face fragments: covered pixel centres, per volume
  std::uint64_t depth_passed = 0;      // passed the inverted depth test (a receiver is there)
  std::uint64_t far_depth_passed = 0;  // + 1. far depth
  std::uint64_t sphere_passed = 0;     // + 2. bounding sphere
  std::uint64_t facing_passed = 0;     // + 3. triangle facing
  std::uint64_t plane_passed = 0;      // + 4. plane distance
  std::uint64_t horizon_passed = 0;    // + 5. hemisphere (horizon)
  std::uint64_t full_skipped = 0;      // passed all five, but the pixel was already fully occluded

  RasterStats& operator+=(const RasterStats& o);
};

/// The counters as lines of text (Table 2 with ratios to horizon_passed when counted), for
/// `exao render --stats`.
[[nodiscard]] std::string format_stats(const RasterStats& stats);

}  // namespace exao::raster
