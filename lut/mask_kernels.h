#pragma once
// exao::lut::MaskKernels: the mask kernels of lut/kernels-inl.h compiled for every instruction
// set of core/isa.h, as tables of function pointers; MaskEngine picks one table when it is built
// (its options, or EXAO_ISA, or the best this CPU runs). The BVH compiles its traversal the same
// way (bvh/traverse_isa.cpp), so its inner loop calls the kernels inline.

#include <cstdint>

#include <glm/glm.hpp>

#include "core/isa.h"
#include "core/mask.h"
#include "core/receiver_frame.h"
#include "lut/plane.h"
#include "lut/plane_table.h"
#include "lut/sample_arrays.h"
#include "lut/triangle_set.h"

namespace exao::lut {

/// Margins of region masks: the sphere is grown by margin * |centre| (lut/sphere_test.h).
/// kTriangleMargin clips triangle masks: only float safety, ~100 float ulps relative.
/// kNodeMargin bounds regions that contain triangle spheres (BVH nodes, influence volumes): it
/// must exceed 2 kTriangleMargin plus the rounding of the node sphere's own arithmetic, so that
/// a node's mask always contains the masks of its triangles (the nesting proof in sphere_test.h).
inline constexpr float kTriangleMargin = 1e-5f;
inline constexpr float kNodeMargin = 1e-4f;

/// The margin, in cosine, by which a cluster's cone must miss a triangle's edge plane or a
/// sphere's cone before the kernels skip the cluster (the proofs in lut/kernels-inl.h).
inline constexpr float kClusterSlack = 1e-4f;

/// What the kernels read: the pattern's arrays, the table (Lut mode) and the radius.
struct KernelContext {
  const SampleArrays* samples = nullptr;
  const PlaneTable* table = nullptr;  // the points table in Lut mode, else nullptr
  float radius = 1.0f;                // r, world units
  float inv_radius = 1.0f;
  bool exact = true;                  // MaskMode::Exact
  bool cull_clusters = true;          // skip the clusters that provably hold no bit
  float cluster_slack = kClusterSlack;
};

/// Work counters of the kernels (summed by a caller that asks for them).
struct KernelCounters {
  std::uint64_t triangle_masks = 0;  // triangles that reached the plane tests (step 6)
  std::uint64_t sphere_masks = 0;    // sphere masks computed (regions and triangle clips)
  std::uint64_t cluster_tests = 0;   // clusters of kSampleCluster samples evaluated by them
  std::uint64_t near_samples = 0;    // samples evaluated one by one (small cones)
  std::uint64_t clip_removed = 0;    // exact masks: bits the clip of step 7 would remove (0)

  KernelCounters& operator+=(const KernelCounters& o) {
    triangle_masks += o.triangle_masks;
    sphere_masks += o.sphere_masks;
    cluster_tests += o.cluster_tests;
    near_samples += o.near_samples;
    clip_removed += o.clip_removed;
    return *this;
  }
};

/// The kernels of one instruction set for masks of Bits bits.
template <int Bits>
struct KernelFunctions {
  Mask<Bits> (*triangle_mask)(const KernelContext&, const TriangleSet&, std::uint32_t, const Frame&,
                              std::uint64_t allowed, KernelCounters*);
  Mask<Bits> (*region_mask)(const KernelContext&, const glm::vec3& centre_local, float radius, float margin,
                            std::uint64_t allowed, KernelCounters*);
  Mask<Bits> (*plane_mask)(const float* x, const float* y, const float* z, const Plane& plane);
};

struct MaskKernels {
  Isa isa = Isa::Scalar;
  KernelFunctions<64> k64;
  KernelFunctions<128> k128;
  KernelFunctions<256> k256;
  KernelFunctions<512> k512;
  KernelFunctions<1024> k1024;

  template <int Bits>
  [[nodiscard]] const KernelFunctions<Bits>& get() const {
    if constexpr (Bits == 64) return k64;
    else if constexpr (Bits == 128) return k128;
    else if constexpr (Bits == 256) return k256;
    else if constexpr (Bits == 512) return k512;
    else return k1024;
  }
};

/// The kernels compiled for `isa` (which the CPU must run: core/isa.h).
[[nodiscard]] const MaskKernels& mask_kernels(Isa isa);

/// The squared distance from the origin to triangle (a, b, c) (Ericson, Real-Time Collision
/// Detection 5.1.5, with p = 0). Float; exact up to rounding. Inline, so the kernels of every
/// level inline it.
[[nodiscard, gnu::always_inline]] inline float origin_triangle_distance2(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) {
  // Ericson's Voronoi-region walk with p = 0: ap = -a, bp = -b, cp = -c.
  const glm::vec3 ab = b - a, ac = c - a;
  const auto dist2 = [](const glm::vec3& q) { return glm::dot(q, q); };
  const float d1 = -glm::dot(ab, a), d2 = -glm::dot(ac, a);
  if (d1 <= 0.0f && d2 <= 0.0f) return dist2(a);
  const float d3 = -glm::dot(ab, b), d4 = -glm::dot(ac, b);
  if (d3 >= 0.0f && d4 <= d3) return dist2(b);
  const float vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0f && d1 >= 0.0f && d3 <= 0.0f) return dist2(a + (d1 / (d1 - d3)) * ab);
  const float d5 = -glm::dot(ab, c), d6 = -glm::dot(ac, c);
  if (d6 >= 0.0f && d5 <= d6) return dist2(c);
  const float vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0f && d2 >= 0.0f && d6 <= 0.0f) return dist2(a + (d2 / (d2 - d6)) * ac);
  const float va = d3 * d6 - d5 * d4;
  if (va <= 0.0f && (d4 - d3) >= 0.0f && (d5 - d6) >= 0.0f) {
    return dist2(b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b));
  }
  const float denom = 1.0f / (va + vb + vc);
  return dist2(a + ab * (vb * denom) + ac * (vc * denom));
}

// One table per level, defined in lut/mask_kernels_isa.cpp (compiled once per level).
namespace scalar_lanes { const MaskKernels& kernels(); }
namespace sse2 { const MaskKernels& kernels(); }
namespace sse4 { const MaskKernels& kernels(); }
namespace avx2 { const MaskKernels& kernels(); }
namespace avx512 { const MaskKernels& kernels(); }

}  // namespace exao::lut
