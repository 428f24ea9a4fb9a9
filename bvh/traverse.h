#pragma once
// exao::bvh::traverse: the occlusion mask of one receiver by BVH traversal with occlusion-ordered
// culling (paper Sec. 5). The answer is exactly the OR of triangle_mask over every triangle
// (lut/brute.h); culling and ordering only skip work:
//  - a child box farther than r (+ rounding slack) or entirely below the horizon holds only
//    triangles whose mask is empty (triangle_mask's steps 5 and 1);
//  - a child whose sphere mask adds no ray to the cumulative mask holds only triangles whose
//    masks add none either (each triangle mask is clipped by its own sphere's mask, which the
//    child's contains: lut/sphere_test.h);
//  - children are visited largest estimate first, so occlusion builds up early;
//  - the kernels evaluate only the clusters of rays that can still change the answer
//    (bvh/traverse-inl.h);
//  - traversal stops when every ray is blocked.
// The loop is compiled for every instruction set of core/isa.h (bvh/traverse_isa.cpp) and runs
// at the engine's level.

#include <cstdint>
#include <string>

#include "bvh/bvh.h"
#include "core/isa.h"
#include "core/mask.h"
#include "core/receiver_frame.h"
#include "lut/mask_engine.h"
#include "lut/mask_kernels.h"

namespace exao::bvh {

/// Work counters of one or more traversals.
struct TraversalStats {
  std::uint64_t receivers = 0;
  std::uint64_t nodes_visited = 0;       // internal nodes whose children were tested
  std::uint64_t triangles_tested = 0;    // triangle_mask calls
  std::uint64_t triangles_blocking = 0;  // triangles that blocked at least one new ray
  std::uint64_t triangles_cached = 0;    // the previous receiver's occluders set up first (OccluderCache)
  lut::KernelCounters kernels;           // plane tests, sphere masks, clusters evaluated
  // The auto method (bvh/hybrid.h):
  std::uint64_t rays = 0;                // rays of its receivers (receivers x N)
  std::uint64_t rays_cast = 0;           // ... of which Embree cast (the rest the masks decided)
  std::uint64_t receivers_stopped = 0;   // receivers whose masks the cost model stopped

  TraversalStats& operator+=(const TraversalStats& o) {
    receivers += o.receivers;
    nodes_visited += o.nodes_visited;
    triangles_tested += o.triangles_tested;
    triangles_blocking += o.triangles_blocking;
    triangles_cached += o.triangles_cached;
    kernels += o.kernels;
    rays += o.rays;
    rays_cast += o.rays_cast;
    receivers_stopped += o.receivers_stopped;
    return *this;
  }
};

/// The cost model of the `auto` method for one receiver (bvh/hybrid.h sets it). Mask work is
/// counted in units (one node's children, or one leaf triangle); the masks stop once
///   units * rays_per_unit > allowance  and  units * rays_per_unit > (rays decided) + allowance,
/// i.e. when what they cost, in Embree rays, exceeds what they have repaid by more than the
/// allowance. Infinite allowance: masks to the end; zero rays_per_unit: the same.
struct MaskBudget {
  float rays_per_unit = 0.0f;
  float allowance = 0.0f;
};

/// What a certain traversal leaves to Embree.
template <int Bits>
struct HybridOutcome {
  Mask<Bits> undecided;     // the rays to cast: all open rays when stopped, else the grazing ones
  std::uint32_t units = 0;  // mask work spent (MaskBudget's units)
  bool complete = false;    // the traversal ran to the end (or every ray was blocked)
};

/// The triangles that blocked new rays at the previous receiver of a run of neighbouring
/// receivers. A traversal given a cache masks these first (they most likely block the same rays
/// here), then traverses as before, and leaves its own occluders in the cache for the next
/// receiver. The masks are the same bits with or without it; only the work changes. One cache
/// per thread and per run of receivers in a coherent order, on one Bvh (each occluder its
/// leaf's place, Bvh::leaf_at, and its lane there).
struct OccluderCache {
  static constexpr int kMax = 64;
  int count = 0;
  std::uint32_t place[kMax];
  std::uint8_t lane[kMax];

  void add(std::uint32_t leaf_place, int leaf_lane) {
    if (count < kMax) place[count] = leaf_place, lane[count++] = static_cast<std::uint8_t>(leaf_lane);
  }
};

namespace detail {

template <int Bits>
struct StackEntry {
  Mask<Bits> mask;  // the child's region mask, to re-check against the grown cumulative mask
  std::uint32_t child;
  std::uint32_t leaf_size;
};

// Deepest stack: (depth 64) x (kMaxChildren - 1) pending siblings, plus one.
inline constexpr int kStackSize = 64 * (kMaxChildren - 1) + 2;

}  // namespace detail

template <int Bits>
struct TraverseFunctions {
  using Function = Mask<Bits> (*)(const Bvh&, const lut::MaskEngine&, const Frame&, TraversalStats*,
                                  const MaskBudget*, HybridOutcome<Bits>*, OccluderCache*);
  Function plain;
  Function counted;
  Function certain;          // the sure mask; the rest in *outcome
  Function certain_counted;
  // For tests: the mask of each triangle of the leaf at `place` (Bvh::leaf_at), through the
  // leaf's set-up in lanes (out[k] for its lane k).
  void (*leaf_masks)(const Bvh&, const lut::MaskEngine&, const Frame&, std::uint32_t place, int count, std::uint64_t allowed,
                     Mask<Bits>* out);
};

struct TraverseTable {
  TraverseFunctions<64> k64;
  TraverseFunctions<128> k128;
  TraverseFunctions<256> k256;
  TraverseFunctions<512> k512;
  TraverseFunctions<1024> k1024;

  template <int Bits>
  [[nodiscard]] const TraverseFunctions<Bits>& get() const {
    if constexpr (Bits == 64) return k64;
    else if constexpr (Bits == 128) return k128;
    else if constexpr (Bits == 256) return k256;
    else if constexpr (Bits == 512) return k512;
    else return k1024;
  }
};

/// The counters per receiver, one line: nodes visited, triangles tested (and how many blocked a
/// new ray), plane tests, sphere masks, and the SIMD vectors they evaluated at `isa`.
[[nodiscard]] std::string format_stats(const TraversalStats& stats, Isa isa);

/// The traversal compiled for `isa` (which the CPU must run).
[[nodiscard]] const TraverseTable& traverse_table(Isa isa);

/// The mask of the receiver whose frame is `frame`, at the engine's instruction set. With
/// `Stats`, counts work into `stats`; with `cache`, masks the previous receiver's occluders
/// first and leaves this one's there. Bits must be engine.bits().
template <int Bits, bool Stats>
[[nodiscard]] Mask<Bits> traverse(const Bvh& bvh, const lut::MaskEngine& engine, const Frame& frame,
                                  TraversalStats* stats, OccluderCache* cache = nullptr) {
  const TraverseFunctions<Bits>& f = traverse_table(engine.isa()).template get<Bits>();
  return (Stats ? f.counted : f.plain)(bvh, engine, frame, stats, nullptr, nullptr, cache);
}

/// The certain traversal of the `auto` method (bvh/traverse-inl.h): returns the rays blocked for
/// sure (Embree's answer on each of them) and puts in *outcome the rays the caller must cast with
/// Embree; every other ray is open in Embree's answer too. budget == nullptr: masks to the end.
/// Exact masks only (engine.mode() == Exact).
template <int Bits, bool Stats>
[[nodiscard]] Mask<Bits> traverse_certain(const Bvh& bvh, const lut::MaskEngine& engine, const Frame& frame,
                                          TraversalStats* stats, const MaskBudget* budget,
                                          HybridOutcome<Bits>& outcome, OccluderCache* cache = nullptr) {
  const TraverseFunctions<Bits>& f = traverse_table(engine.isa()).template get<Bits>();
  return (Stats ? f.certain_counted : f.certain)(bvh, engine, frame, stats, budget, &outcome, cache);
}

/// Each triangle's mask of the leaf at `place` (a Node::child of a leaf slot, Bvh::leaf_at)
/// that holds `count` triangles, at the engine's instruction set, computed as the
/// traversal computes it: the leaf's set-up in lanes, then the rest per triangle. For
/// tests/triangle_mask_test.cpp, which checks it against lut's one-triangle kernel.
template <int Bits>
void leaf_masks(const Bvh& bvh, const lut::MaskEngine& engine, const Frame& frame, std::uint32_t place, int count,
                std::uint64_t allowed, Mask<Bits>* out) {
  traverse_table(engine.isa()).template get<Bits>().leaf_masks(bvh, engine, frame, place, count, allowed, out);
}

namespace scalar_lanes { const TraverseTable& traverse_table(); }
namespace sse2 { const TraverseTable& traverse_table(); }
namespace sse4 { const TraverseTable& traverse_table(); }
namespace avx2 { const TraverseTable& traverse_table(); }
namespace avx512 { const TraverseTable& traverse_table(); }

}  // namespace exao::bvh
