#pragma once
// exao::bvh::build_topology: the shape of the BVH, by a parallel binned SAH build over TBB, the
// algorithm of Embree's own binned builder (Wald 2007; Embree's GeneralBVHBuilder): 32 bins on
// the axis of the centroid box, a leaf where the SAH says so, and an N-wide node made by
// splitting its child of largest area until it has N children. Only the topology: the packing of
// the leaves into PackedTriangle and LeafBlock, and the node spheres, are Bvh::build's.

#include <cstdint>
#include <functional>
#include <vector>

#include "bvh/bvh.h"
#include "core/error.h"
#include "core/progress.h"

namespace exao::bvh {

/// One triangle as the builder sees it: its box, and its index in the caller's order.
struct BuildPrimitive {
  float lo_x, lo_y, lo_z;
  std::uint32_t index;
  float hi_x, hi_y, hi_z;
  float unused;
};
static_assert(sizeof(BuildPrimitive) == 32);

/// Embree's costs (rtcBuildBVH's traversalCost and intersectionCost, as bvh.cpp gave them):
/// the tree then visits the nodes and triangles Embree's did, within 0.5%. A lower intersection
/// cost makes fuller leaves (0.3: 3.2 triangles a leaf on Conference, not 1.5, so a third of
/// the LeafBlock bytes) at more triangle tests a receiver: see docs/scale.md.
struct SahCosts {
  float traversal = 1.0f;     // of a node, per unit of its half area
  float intersection = 1.0f;  // of a triangle, per unit of its leaf's half area
};

/// The tree, flattened depth first (nodes[0] the root), boxes, children and leaf sizes set; the
/// spheres left zero. Child k of node i holds the triangles order[first[i][k] .. last[i][k]).
struct Topology {
  std::vector<Node> nodes;
  struct SlotRange {
    std::uint32_t first[kMaxChildren];
    std::uint32_t last[kMaxChildren];
  };
  std::vector<SlotRange> ranges;      // per node
  std::vector<std::uint32_t> order;   // leaf order: the caller's index of every triangle
};

/// Builds over `primitives` (reordered in place; at least one). Fails only when the tree would
/// be deeper than traversal's stack allows (64 levels), which takes millions of triangles with
/// the same centroid. `progress` gets (triangles placed in leaves, total).
[[nodiscard]] Result<Topology> build_topology(std::vector<BuildPrimitive>& primitives, const BvhOptions& options,
                                              const SahCosts& costs = {}, const ProgressCallback& progress = {});

}  // namespace exao::bvh
