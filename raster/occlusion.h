#pragma once
// exao::raster::occlusion: the `raster` backend (DESIGN.md section 5; the paper's Method 1,
// Sec. 4) in software. For a camera image:
//  1. a rasterised G-buffer gives each pixel's receiver (raster/gbuffer.h);
//  2. the occlusion buffers (one N-bit mask per receiver) start empty;
//  3. for each triangle, an influence volume (raster/influence_volume.h) is built and its far
//     faces rasterised with the top-left rule; a fragment passes the inverted depth test when
//     the far surface is at or behind the receiver, then runs the five culling tests in the
//     paper's order (raster/fragment_tests.h), and survivors OR engine.triangle_mask into the
//     pixel's buffer.
// The screen is cut into tiles; triangles are binned to the tiles their volumes cover and TBB
// tasks draw whole tiles, so each buffer has one writer. A volume skips whole tiles and tile rows
// whose receivers' bounds fail the depth test or tests 1 and 2, and the first tests run on a
// span of pixels at once (vectorised). The volumes and tests are conservative, so the masks
// equal the BVH and brute backends' bit for bit (DESIGN.md section 8, test 2).

#include <span>

#include "core/camera.h"
#include "core/mask_set.h"
#include "core/pixel_receivers.h"
#include "core/progress.h"
#include "core/scene.h"
#include "lut/mask_engine.h"
#include "lut/triangle_set.h"
#include "raster/distance_range.h"
#include "raster/stats.h"

namespace exao::raster {

struct RasterOptions {
  /// R / r above which a triangle's volume is the hexagonal prism, else the billboard (paper
  /// Sec. 4.1, where 0.2 was consistently good). > 0.
  float alpha = 0.2f;
  /// Count fragments at every culling stage (RasterStats' second half: the paper's Table 2).
  /// Slower: every fragment is counted one by one, and the culls that skip a whole tile or tile
  /// row when none of its receivers can pass tests 1 and 2 are off (they would hide fragments
  /// from the counts; the masks are the same either way).
  bool stats = false;
  /// After the five tests, skip a fragment when the mask of the triangle's bounding sphere
  /// (region_mask, kNodeMargin: it holds the triangle's mask) adds no ray to the pixel's buffer:
  /// the BVH's node test (paper Sec. 5) per fragment. Exact, several times cheaper than most
  /// triangle masks it saves (those of small, distant triangles, which mostly block nothing).
  /// Off: masks exactly for the fragments that pass the paper's five tests (Table 2).
  bool sphere_mask_cull = true;
  /// For tests only: shrink every volume's reach by this fraction of r, so that a test can check
  /// that the equality with the BVH catches a volume that is too small. 0 in real use.
  float test_shrink = 0.0f;
  /// Level of detail (paper Sec. 4.3, raster/lod.h): one distance range per triangle of the
  /// triangle set, which then holds every level's triangles. A triangle's volume and fragment
  /// tests use its r_max in place of r, and its mask is range_mask (raster/distance_range.h).
  /// Empty (the default): every triangle takes [0, r] and the masks are exact.
  std::span<const DistanceRange> ranges;
};

struct RasterResult {
  PixelReceivers pixels;  // the G-buffer's receivers, in pixel order
  MaskSet masks;          // one row per receiver, in the same order
  RasterStats stats;
};

/// Ambient-occlusion masks of every pixel of a width x height image (1 .. 16384 each) of
/// `camera`. `triangles` must be TriangleSet::build(scene); `engine` gives the rays (N, r, eps)
/// and the one mask function. Multithreaded with TBB; progress in tiles.
[[nodiscard]] RasterResult occlusion(const Scene& scene, const lut::TriangleSet& triangles, const lut::MaskEngine& engine,
                                     const Camera& camera, int width, int height, const RasterOptions& options = {},
                                     const ProgressCallback& progress = {});

/// The same for receivers the caller already has: `pixels` must be pixel receivers of this
/// camera and image size (raster_pixel_receivers, or core's Embree pixel_receivers; at most one
/// receiver per pixel). The result's `pixels` is a copy of them.
[[nodiscard]] RasterResult occlusion(const PixelReceivers& pixels, const Scene& scene, const lut::TriangleSet& triangles,
                                     const lut::MaskEngine& engine, const Camera& camera,
                                     const RasterOptions& options = {}, const ProgressCallback& progress = {});

}  // namespace exao::raster
