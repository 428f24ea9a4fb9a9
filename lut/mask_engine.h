#pragma once
// exao::lut::MaskEngine: THE triangle mask of DESIGN.md section 4, and the conservative region
// masks of bounding spheres, for one set of shadow rays. Every backend (brute, bvh, raster) calls
// these functions and nothing else to turn geometry into bits, which is what makes the
// equalities of DESIGN.md section 8 exact.
//
// Units: triangle_mask and region_mask take world-space geometry (TriangleSet, or centres that
// the caller moved into the receiver frame with Frame::to_local, still in world units); the
// engine works internally in normalised units (r = 1), like the pattern and the plane table.
//
// Rules for a backend that wants the same bits as brute (DESIGN.md section 8):
//  - Cull only what triangle_mask provably rejects. Its tests run in float in the receiver
//    frame; a backend culling by its own arithmetic (a box distance or a box's corners below the
//    horizon, in world space) must leave room for the rounding of both: cull at distance
//    > r + reach_slack(...), or below the horizon only when every corner has z < -reach_slack.
//  - Or cull by masks: region_mask(node sphere, kNodeMargin) holds every triangle mask inside
//    the node, provided the node sphere holds its triangles' stored spheres (TriangleSet::centre,
//    radius) in exact arithmetic on the floats: round the node radius up.
//  - Run mask work inside a lut::FlushDenormals (lut/float_mode.h), as brute does: Embree leaves
//    FTZ/DAZ on in the TBB workers it ran on, and the bits must not depend on the thread.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <string>

#include <glm/glm.hpp>

#include "core/error.h"
#include "core/mask.h"
#include "core/receiver_frame.h"
#include "core/shadow_rays.h"
#include "lut/sphere_test.h"
#include "lut/lanes.h"
#include "lut/plane_table.h"
#include "lut/sample_arrays.h"
#include "lut/triangle_set.h"

namespace exao::lut {

/// Where plane masks come from: the plane table (the paper's way, the default) or the exact
/// test of all N sample points.
enum class MaskMode { Lut, Exact };

[[nodiscard]] const char* mask_mode_name(MaskMode mode);
/// "lut" or "exact"; the error names the option --masks.
[[nodiscard]] Result<MaskMode> parse_mask_mode(const std::string& name);

/// Margins of region masks: the sphere is grown by margin * |centre| (lut/sphere_test.h).
/// kTriangleMargin clips triangle masks: only float safety, ~100 float ulps relative.
/// kNodeMargin bounds regions that contain triangle spheres (BVH nodes, influence volumes): it
/// must exceed 2 kTriangleMargin plus the rounding of the node sphere's own arithmetic, so that
/// a node's mask always contains the masks of its triangles (the nesting proof in sphere_test.h).
inline constexpr float kTriangleMargin = 1e-5f;
inline constexpr float kNodeMargin = 1e-4f;

class MaskEngine {
 public:
  MaskEngine() = default;

  /// Engine for `rays`. Mode Lut builds the points plane table at `resolution` (0: the default
  /// for N, see lut/plane_table.h); mode Exact builds no table. Fails on a bad resolution.
  [[nodiscard]] static Result<MaskEngine> build(const ShadowRays& rays, MaskMode mode, int resolution = 0);

  /// Lut-mode engine with a table the caller built or loaded; it must be a Points table of the
  /// rays' pattern (else an error saying so).
  [[nodiscard]] static Result<MaskEngine> with_table(const ShadowRays& rays, PlaneTable table);

  [[nodiscard]] const ShadowRays& rays() const { return rays_; }
  [[nodiscard]] MaskMode mode() const { return mode_; }
  [[nodiscard]] int samples() const { return rays_.count(); }   // N
  [[nodiscard]] int bits() const { return samples_.bits(); }    // mask width, mask_bits_for(N)
  [[nodiscard]] const SampleArrays& sample_arrays() const { return samples_; }
  /// The points table (mode Lut), else nullptr.
  [[nodiscard]] const PlaneTable* table() const { return table_ ? &*table_ : nullptr; }
  [[nodiscard]] int table_resolution() const { return table_ ? table_->resolution() : 0; }
  [[nodiscard]] std::size_t table_bytes() const { return table_ ? table_->memory_bytes() : 0; }

  /// All N rays: the mask of a receiver that is fully occluded.
  template <int Bits>
  [[nodiscard]] Mask<Bits> all_rays() const { return Mask<Bits>::ones(samples()); }

  /// The rays triangle t of `triangles` blocks at the receiver of `frame` (DESIGN.md section 4).
  /// Steps, in this order, each returning the empty mask when the triangle cannot block a ray:
  ///  1. the vertices into the frame; all of them at z <= 0 (at or below the horizon);
  ///  2. one-sided and the origin not strictly in front of the counter-clockwise face;
  ///  3. degenerate (zero or non-finite normal), or plane distance d > r, or d == 0 (the origin
  ///     in the triangle's plane: no ray crosses it);
  ///  4. the origin outside the influence sphere: |centre| > radius + r;
  ///  5. the exact distance from the origin to the triangle > r;
  ///  6. the four plane masks AND-ed: three edge planes through the origin (normal
  ///     cross(va, vb), oriented to the third vertex) and the triangle's plane (oriented away
  ///     from the origin, distance d), from the table (Lut) or by testing every sample point;
  ///  6b. the origin on the triangle's plane (core/surface_rule.h: such a triangle blocks no
  ///     ray), decided by origin_on_plane on the world-space floats;
  ///  7. AND region_mask(the triangle's sphere, kTriangleMargin): a table mask can carry bits far
  ///     from the triangle (a sliver's discretised edge planes), and this clip is what makes
  ///     every bounding region's mask (same function, bigger sphere, bigger margin) a superset.
  /// Bits must be bits(). L picks the lanes (the scalar twin for tests); the default is the
  /// instruction set of core/mask.h.
  template <int Bits, class L = NativeLanes>
  [[nodiscard]] Mask<Bits> triangle_mask(const TriangleSet& triangles, std::uint32_t t, const Frame& frame) const;

  /// Conservative mask of a sphere: every ray i whose segment [0, l_i r w_i] can meet the
  /// sphere of `radius` (world units) at `centre_local` (receiver frame, world units) is set:
  /// exactly the rays that meet the sphere grown by margin * |centre_local| (lut/sphere_test.h);
  /// all ones when the origin is inside, none when the sphere is entirely below the horizon.
  /// Exact per ray, vectorised over the N rays. A sphere S holding a sphere T gives a superset
  /// of T's mask when S's margin >= 2 x T's margin + rounding (kNodeMargin vs kTriangleMargin).
  template <int Bits, class L = NativeLanes>
  [[nodiscard]] Mask<Bits> region_mask(const glm::vec3& centre_local, float radius, float margin) const;

  /// The mask of one plane (normalised units): the table's cell (Lut) or the exact test.
  template <int Bits, class L = NativeLanes>
  [[nodiscard]] Mask<Bits> plane_mask(const Plane& plane) const;

  /// Slack (world units) a backend adds to r before culling by its own distance computations,
  /// for geometry within `extent` (world units) of a receiver at `origin`: covers float
  /// rounding of both sides (relative errors of a few 1e-7 on lengths up to |origin| + extent).
  [[nodiscard]] float reach_slack(const glm::vec3& origin, float extent) const {
    const float largest = std::max(std::abs(origin.x), std::max(std::abs(origin.y), std::abs(origin.z)));
    return 1e-5f * (largest + extent + rays_.radius);
  }

 private:
  ShadowRays rays_;
  MaskMode mode_ = MaskMode::Exact;
  float inv_radius_ = 1.0f;
  SampleArrays samples_;
  std::optional<PlaneTable> table_;
};

/// The squared distance from the origin to triangle (a, b, c) (Ericson, Real-Time Collision
/// Detection 5.1.5, with p = 0). Float; exact up to rounding.
[[nodiscard]] float origin_triangle_distance2(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c);

}  // namespace exao::lut
