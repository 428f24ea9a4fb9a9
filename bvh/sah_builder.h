#pragma once
// exao::bvh::build_topology: the shape of the BVH, by a parallel binned SAH build over TBB, the
// algorithm of Embree's own binned builder (Wald 2007; Embree's GeneralBVHBuilder): 32 bins on
// the axis of the centroid box, a leaf where the SAH says so, and an N-wide node made by
// splitting its child of largest area until it has N children. Only the topology: the packing of
// the leaf blocks and the node spheres, are Bvh::build's.

#include <cstdint>
#include <functional>
#include <vector>

#include "bvh/bvh.h"
#include "core/default_init_allocator.h"
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
using BuildPrimitives = std::vector<BuildPrimitive, DefaultInitAllocator<BuildPrimitive>>;

/// Embree's costs (rtcBuildBVH's traversalCost and intersectionCost, as bvh.cpp gave them):
/// the tree then visits the nodes and triangles Embree's did, within 0.5%. A lower intersection
/// cost makes fuller leaves (0.3: 3.2 triangles a leaf on Conference, not 1.5, so a third of
/// the LeafBlock bytes) at more triangle tests a receiver: see docs/scale.md.
// A triangle costs less than a node here, unlike in a ray tracer: a leaf's triangles are set up
// together in lanes (bvh/leaf_setup-inl.h), so a fuller leaf costs little more than a
// half-empty one, while each node costs four sphere masks. Measured (one run each, avx512,
// Conference pixels N = 128 and 2CylinderEngine's vertices at 5%): intersection 0.3 gives about
// 3 triangles a leaf instead of 1.5, bvh 1.3-1.4x faster at 1% and on the vertices, the same at
// 5% on pixels, and half the leaf blocks' memory.
struct SahCosts {
  float traversal = 1.0f;     // of a node, per unit of its half area
  float intersection = 0.3f;  // of a triangle, per unit of its leaf's half area
};

/// The tree, flattened depth first (nodes[0] the root), boxes, children and leaf sizes set; the
/// spheres left zero. A leaf slot's child is its first triangle in `order`.
struct Topology {
  std::vector<Node, DefaultInitAllocator<Node>> nodes;
  std::vector<std::uint32_t> order;   // leaf order: the caller's index of every triangle
};

/// Builds over `primitives` (at least one; freed once the leaf order is taken from them). Fails only when the tree would
/// be deeper than traversal's stack allows (64 levels), which takes millions of triangles with
/// the same centroid. `progress` gets (triangles placed in leaves, total).
[[nodiscard]] Result<Topology> build_topology(BuildPrimitives& primitives, const BvhOptions& options,
                                              const SahCosts& costs = {}, const ProgressCallback& progress = {});

}  // namespace exao::bvh
