#pragma once
// exao::bvh::Bvh: the scene's triangles in a bounding volume hierarchy built by a parallel binned
// SAH builder (bvh/sah_builder.h, Embree's algorithm), in exao's own compact layout: every node holds the boxes
// and bounding spheres of its (up to four) children side by side, so that one receiver tests all
// children of a node in one pass (paper Sec. 5).

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "core/cutouts.h"
#include "core/error.h"
#include "core/progress.h"
#include "core/scene.h"
#include "lut/sample_arrays.h"
#include "lut/triangle_set.h"

namespace exao::bvh {

inline constexpr int kMaxChildren = 4;

/// One internal node. Child slot k is used when k < child_count.
struct Node {
  float lo_x[kMaxChildren], lo_y[kMaxChildren], lo_z[kMaxChildren];  // child boxes, world units
  float hi_x[kMaxChildren], hi_y[kMaxChildren], hi_z[kMaxChildren];
  float centre_x[kMaxChildren], centre_y[kMaxChildren], centre_z[kMaxChildren];  // child spheres,
  float radius[kMaxChildren];  // holding every triangle sphere below (so region masks nest)
  std::uint32_t child[kMaxChildren];  // internal: node index; leaf: first triangle
  std::uint8_t leaf_size[kMaxChildren];  // 0 for an internal child, else its triangle count (1-8)
  std::uint8_t child_count;
};

/// A leaf's triangles side by side, lane k = the leaf's triangle k (the same floats as `packed`),
/// lanes past the leaf's size NaN: the traversal (bvh and auto) sets up a whole leaf at once,
/// lane = triangle (bvh/leaf_setup-inl.h).
struct alignas(32) LeafBlock {
  static constexpr int kLanes = 8;
  float v0x[kLanes], v0y[kLanes], v0z[kLanes];
  float v1x[kLanes], v1y[kLanes], v1z[kLanes];
  float v2x[kLanes], v2y[kLanes], v2z[kLanes];
  float cx[kLanes], cy[kLanes], cz[kLanes];  // bounding spheres
  float radius[kLanes];
  std::uint32_t two_sided = 0;  // bit k: lane k is two-sided
  std::uint32_t cutout = 0;     // bit k: lane k is alpha-tested (0 in an opaque scene: today's path)
};

struct BvhOptions {
  int branching = 4;     // 2 or 4 children per node (Embree's maxBranchingFactor)
  int max_leaf_size = 8; // triangles per leaf, 1-8 (paper Sec. 6)
};

/// Checks both fields; the error names the field ("bvh.branching") and its value.
[[nodiscard]] Result<void> check_options(const BvhOptions& options);

struct Bvh {
  std::vector<Node> nodes;          // nodes[0] is the root
  // The triangles in leaf order (a leaf's are contiguous), a cache line each: the same floats as
  // lut::TriangleSet's, so every mask equals brute's.
  std::vector<lut::PackedTriangle, lut::CacheLineAllocator<lut::PackedTriangle>> packed;
  std::vector<std::uint32_t> scene_triangle;  // index in the scene of packed[i]
  /// The scene's cut-outs when any triangle is alpha-tested (PackedTriangle::cutout), else null.
  std::shared_ptr<const Cutouts> cutouts;
  float largest_coordinate = 0.0f;             // max |coordinate| of every vertex (the grazing margin's scale)
  float box_shrink_for_test = 0.0f;            // world units off the box cull's margin: a test's too-tight cull
  std::vector<LeafBlock, lut::CacheLineAllocator<LeafBlock>> blocks;  // one per leaf
  std::vector<std::uint32_t> leaf_block;       // per triangle that starts a leaf: its block

  /// Builds over `triangles` (copied in leaf order: the floats are the same, so every mask
  /// equals brute's). Fails on an empty set, or a tree deeper than 64 levels (millions of
  /// triangles with one centroid). Multithreaded (TBB); `progress` gets (done, total) work units.
  [[nodiscard]] static Result<Bvh> build(const lut::TriangleSet& triangles, const BvhOptions& options = {},
                                         const ProgressCallback& progress = {});
  /// The same tree and floats from the scene directly, without a TriangleSet (53 bytes a
  /// triangle fewer at the peak): the spheres are computed as TriangleSet::build computes them.
  [[nodiscard]] static Result<Bvh> build(const Scene& scene, const BvhOptions& options = {},
                                         const ProgressCallback& progress = {});
  /// The same tree, freeing the scene's arrays (scene = Scene{}, on success or failure after the
  /// topology) once the packed copy is made, before the leaf blocks: the scene's 41 bytes a
  /// triangle are then not part of the peak.
  [[nodiscard]] static Result<Bvh> build(Scene&& scene, const BvhOptions& options = {},
                                         const ProgressCallback& progress = {});

  /// Refit after a deformation: `vertices` are the triangles build was given (3 per triangle,
  /// in the scene's order; sidedness, objects and cut-outs kept), at new positions. The tree keeps its topology; every box
  /// and sphere, the leaf blocks and the packed floats are recomputed bottom-up from the new
  /// triangles, as conservative as build's, so the masks are brute's bit for bit as after a fresh
  /// build (only the culling's speed may drop when triangles move far from their old
  /// neighbours). Single-threaded, linear in the size.
  void refit(std::span<const glm::vec3> vertices);
};

/// What a BVH holds, in bytes by array (capacities: what the process pays for them).
struct BvhBytes {
  std::size_t nodes = 0;    // Node, 184 bytes each
  std::size_t blocks = 0;   // LeafBlock, 448 bytes a leaf whatever its size
  std::size_t packed = 0;   // PackedTriangle, 64 bytes a triangle
  std::size_t indices = 0;  // scene_triangle and leaf_block, 4 bytes a triangle each
  [[nodiscard]] std::size_t total() const { return nodes + blocks + packed + indices; }
};
[[nodiscard]] BvhBytes memory_bytes(const Bvh& bvh);

/// The lanes of a leaf (bit k: triangle first + k, k < count) that belong to `object`: the
/// triangles a receiver excluding it skips (Receiver::excluded_object).
[[nodiscard]] inline std::uint32_t object_lanes(const Bvh& bvh, std::uint32_t first, int count, std::uint32_t object) {
  std::uint32_t lanes = 0;
  for (int k = 0; k < count; ++k) lanes |= static_cast<std::uint32_t>(bvh.packed[first + k].object == object) << k;
  return lanes;
}

}  // namespace exao::bvh
