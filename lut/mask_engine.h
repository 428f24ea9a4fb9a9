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
// Instruction sets: the kernels are compiled for every level of core/isa.h (lut/mask_kernels.h)
// and the engine picks one when it is built; every level gives the same bits.
//
// Clusters: every mask function takes an optional set of clusters (lut/sample_arrays.h; bit k
// stands for samples [16 k, 16 k + 16)) and returns the full mask AND those clusters' bits,
// computing nothing for the others. A caller that only ORs masks into a cumulative mask passes
// the clusters where it still has open rays, which changes nothing in the OR.
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

#include "core/enum_names.h"
#include "core/error.h"
#include "core/isa.h"
#include "core/mask.h"
#include "core/receiver_frame.h"
#include "core/shadow_rays.h"
#include "lut/cutout_filter.h"
#include "lut/mask_kernels.h"
#include "lut/plane_table.h"
#include "lut/sample_arrays.h"
#include "lut/triangle_set.h"

namespace exao::lut {

/// Where plane masks come from: the plane table (the paper's way) or the exact test of all N
/// sample points (the default: faster on every level measured, and exact).
enum class MaskMode { Lut, Exact };

[[nodiscard]] constexpr auto enum_names(MaskMode) {
  return std::to_array<EnumName<MaskMode>>({{MaskMode::Lut, "lut"}, {MaskMode::Exact, "exact"}});
}

[[nodiscard]] const char* mask_mode_name(MaskMode mode);
/// "lut" or "exact"; the error names the option "masks".
[[nodiscard]] Result<MaskMode> parse_mask_mode(const std::string& name);

class MaskEngine {
 public:
  MaskEngine() = default;

  /// Engine for `rays`. Mode Lut builds the points plane table at `resolution` (0: the default
  /// for N, see lut/plane_table.h); mode Exact builds no table. `isa`: the kernels' instruction
  /// set (nullopt: core/isa.h's default_isa()). Fails on a bad resolution or a level this CPU
  /// does not run.
  [[nodiscard]] static Result<MaskEngine> build(const ShadowRays& rays, MaskMode mode, int resolution = 0,
                                                std::optional<Isa> isa = std::nullopt);

  /// Lut-mode engine with a table the caller built or loaded; it must be a Points table of the
  /// rays' pattern (else an error saying so).
  [[nodiscard]] static Result<MaskEngine> with_table(const ShadowRays& rays, PlaneTable table,
                                                     std::optional<Isa> isa = std::nullopt);

  // Movable (the kernel context points into the engine, so a move re-points it), not copyable
  // (the plane table is tens of MiB).
  MaskEngine(MaskEngine&& o) noexcept { *this = std::move(o); }
  MaskEngine& operator=(MaskEngine&& o) noexcept;

  [[nodiscard]] const ShadowRays& rays() const { return rays_; }
  [[nodiscard]] MaskMode mode() const { return mode_; }
  [[nodiscard]] Isa isa() const { return kernels_->isa; }
  [[nodiscard]] int samples() const { return rays_.count(); }   // N
  [[nodiscard]] int bits() const { return samples_.bits(); }    // mask width, mask_bits_for(N)
  [[nodiscard]] const SampleArrays& sample_arrays() const { return samples_; }
  /// The points table (mode Lut), else nullptr.
  [[nodiscard]] const PlaneTable* table() const { return table_ ? &*table_ : nullptr; }
  [[nodiscard]] int table_resolution() const { return table_ ? table_->resolution() : 0; }
  [[nodiscard]] std::size_t table_bytes() const { return table_ ? table_->memory_bytes() : 0; }
  /// What the kernels read, for a backend that runs them inline (bvh/traverse_isa.cpp).
  [[nodiscard]] const KernelContext& kernel_context() const { return context_; }

  /// For tests of the cluster culling only: slack (default kClusterSlack; a negative one culls
  /// too much, which the tests must notice) and culling on or off.
  void set_cluster_culling_for_test(bool cull, float slack) {
    context_.cull_clusters = cull;
    context_.cluster_slack = slack;
  }

  /// All N rays: the mask of a receiver that is fully occluded.
  template <int Bits>
  [[nodiscard]] Mask<Bits> all_rays() const { return Mask<Bits>::ones(samples()); }

  /// The rays triangle t of `triangles` blocks at the receiver of `frame` (DESIGN.md section 4),
  /// restricted to `allowed` clusters. Steps, in this order, each returning the empty mask when
  /// the triangle cannot block a ray:
  ///  1. the vertices into the frame; all of them at z <= 0 (at or below the horizon);
  ///  2. one-sided and the origin not strictly in front of the counter-clockwise face;
  ///  3. degenerate (zero or non-finite normal), or plane distance d > r, or d == 0 (the origin
  ///     in the triangle's plane: no ray crosses it);
  ///  4. the origin outside the influence sphere: |centre| > radius + r;
  ///  5. the exact distance from the origin to the triangle > r;
  ///  6. the four plane masks AND-ed: three edge planes through the origin (normal
  ///     cross(va, vb), times the sign of det(a, b, c) = dot(n, a) so that the third vertex is on
  ///     the positive side) and the triangle's plane (oriented away from the origin, distance d),
  ///     from the table (Lut) or by testing every sample point of the clusters the triangle can
  ///     reach (Exact). The edge normals stay unnormalised: a plane through the origin tests the
  ///     same points at any scale. A (near-)zero edge normal (an edge through the origin, or a
  ///     product under 1e-30, far from the denormals where FTZ could matter) blocks nothing;
  ///  6b. the origin on the triangle's plane (core/surface_rule.h: such a triangle blocks no
  ///     ray), decided by origin_on_plane on the world-space floats;
  ///  7. AND region_mask(the triangle's sphere, kTriangleMargin): a table mask can carry bits far
  ///     from the triangle (a sliver's discretised edge planes), and this clip is what makes
  ///     every bounding region's mask (same function, bigger sphere, bigger margin) a superset.
  /// Bits must be bits(). With `counters`, counts the work.
  template <int Bits>
  [[nodiscard]] Mask<Bits> triangle_mask(const TriangleSet& triangles, std::uint32_t t, const Frame& frame,
                                         std::uint64_t allowed = kAllClusters<Bits>,
                                         KernelCounters* counters = nullptr) const {
    Mask<Bits> mask = kernels_->get<Bits>().triangle_mask(context_, triangles, t, frame, allowed, counters);
    // A cut-out triangle (t is the scene's index: a TriangleSet in scene order) keeps the bits its alpha blocks.
    if (triangles.cutouts && triangles.cutout[t] && mask.any()) keep_cutout_hits(*triangles.cutouts, t, rays(), frame, mask.words);
    return mask;
  }

  /// Conservative mask of a sphere: every ray i whose segment [0, l_i r w_i] can meet the
  /// sphere of `radius` (world units) at `centre_local` (receiver frame, world units) is set:
  /// exactly the rays that meet the sphere grown by margin * |centre_local| (lut/sphere_test.h);
  /// all ones when the origin is inside, none when the sphere is entirely below the horizon.
  /// Exact per ray, vectorised over the N rays. A sphere S holding a sphere T gives a superset
  /// of T's mask when S's margin >= 2 x T's margin + rounding (kNodeMargin vs kTriangleMargin).
  template <int Bits>
  [[nodiscard]] Mask<Bits> region_mask(const glm::vec3& centre_local, float radius, float margin,
                                       std::uint64_t allowed = kAllClusters<Bits>,
                                       KernelCounters* counters = nullptr) const {
    return kernels_->get<Bits>().region_mask(context_, centre_local, radius, margin, allowed, counters);
  }

  /// The mask of one plane (normalised units): the table's cell (Lut) or the exact test.
  template <int Bits>
  [[nodiscard]] Mask<Bits> plane_mask(const Plane& plane) const {
    if (mode_ == MaskMode::Lut) return table_->lookup<Bits>(plane.m, plane.d);
    return kernels_->get<Bits>().plane_mask(samples_.px(), samples_.py(), samples_.pz(), plane);
  }

  /// Slack (world units) a backend adds to r before culling by its own distance computations,
  /// for geometry within `extent` (world units) of a receiver at `origin`: covers float
  /// rounding of both sides (relative errors of a few 1e-7 on lengths up to |origin| + extent).
  [[nodiscard]] float reach_slack(const glm::vec3& origin, float extent) const {
    const float largest = std::max(std::abs(origin.x), std::max(std::abs(origin.y), std::abs(origin.z)));
    return 1e-5f * (largest + extent + rays_.radius);
  }

 private:
  void bind();  // points context_ at this engine's own arrays and table

  ShadowRays rays_;
  MaskMode mode_ = MaskMode::Exact;
  SampleArrays samples_;
  std::optional<PlaneTable> table_;
  const MaskKernels* kernels_ = &mask_kernels(Isa::Scalar);
  KernelContext context_;
};

}  // namespace exao::lut
