#pragma once
// exao::bvh::Bvh: the scene's triangles in a bounding volume hierarchy built by a parallel binned
// SAH builder (bvh/sah_builder.h, Embree's algorithm), in exao's own compact layout: every node holds the boxes
// and bounding spheres of its (up to four) children side by side, so that one receiver tests all
// children of a node in one pass (paper Sec. 5).

#include <cstdint>
#include <cstring>
#include <memory>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "core/cutouts.h"
#include "core/default_init_allocator.h"
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
  std::uint32_t child[kMaxChildren];  // internal: node index; leaf: its place in Bvh::leaf_floats (leaf_at)
  std::uint8_t leaf_size[kMaxChildren];  // 0 for an internal child, else its triangle count (1-8)
  std::uint8_t child_count;
};

/// The rows of a leaf's lanes (LeafBlock), in the order Bvh::leaf_floats holds them.
enum LeafRow : int { kV0x, kV0y, kV0z, kV1x, kV1y, kV1z, kV2x, kV2y, kV2z, kCentreX, kCentreY, kCentreZ, kRadius, kLeafRows };

/// A leaf's triangles side by side, lane k = the leaf's triangle k (the floats of
/// lut::TriangleSet, so every mask equals brute's): the traversal (bvh and auto) sets up a whole
/// leaf at once, lane = triangle (bvh/leaf_setup-inl.h). A view of kLeafRows rows of `width`
/// floats: 2 for a leaf of up to 2 triangles, 4 up to 4, else 8. Most leaves are small (2.75
/// triangles on average on a terrain, 70% of its leaves hold 2), so narrow rows cut the bytes
/// of the tree's largest part by more than half; the set-up reads a narrow row into 8 lanes with
/// NaN above (load_row), so lanes past the leaf's size are NaN, as they were when every row had 8.
struct LeafBlock {
  static constexpr int kLanes = 8;
  const float* rows;            // kLeafRows rows of `width` floats
  int width;                    // 2, 4 or 8
  std::uint32_t two_sided;      // bit k: lane k is two-sided
  std::uint32_t cutout;         // bit k: lane k is alpha-tested (0 in an opaque scene: today's path)
  std::uint32_t first;          // lane 0's triangle, in leaf order
  std::uint32_t count;          // the leaf's size, 1-8

  [[nodiscard, gnu::always_inline]] const float* row(int r) const { return rows + r * width; }
  [[nodiscard, gnu::always_inline]] const float* v0x() const { return row(kV0x); }
  [[nodiscard, gnu::always_inline]] const float* v0y() const { return row(kV0y); }
  [[nodiscard, gnu::always_inline]] const float* v0z() const { return row(kV0z); }
  [[nodiscard, gnu::always_inline]] const float* v1x() const { return row(kV1x); }
  [[nodiscard, gnu::always_inline]] const float* v1y() const { return row(kV1y); }
  [[nodiscard, gnu::always_inline]] const float* v1z() const { return row(kV1z); }
  [[nodiscard, gnu::always_inline]] const float* v2x() const { return row(kV2x); }
  [[nodiscard, gnu::always_inline]] const float* v2y() const { return row(kV2y); }
  [[nodiscard, gnu::always_inline]] const float* v2z() const { return row(kV2z); }
  [[nodiscard, gnu::always_inline]] const float* cx() const { return row(kCentreX); }  // bounding spheres
  [[nodiscard, gnu::always_inline]] const float* cy() const { return row(kCentreY); }
  [[nodiscard, gnu::always_inline]] const float* cz() const { return row(kCentreZ); }
  [[nodiscard, gnu::always_inline]] const float* radius() const { return row(kRadius); }
};

/// Floats a row of a leaf of `count` triangles.
[[nodiscard]] constexpr int leaf_width(int count) { return count <= 2 ? 2 : count <= 4 ? 4 : LeafBlock::kLanes; }

/// What precedes a leaf's rows in Bvh::leaf_floats (16 bytes; the rows are read unaligned): a
/// node's child slot leads to the header and the rows together, one place in memory.
struct LeafHeader {
  std::uint32_t first;      // lane 0's triangle, in leaf order
  std::uint8_t count;       // 1-8
  std::uint8_t two_sided;   // bit k: lane k is two-sided
  std::uint8_t cutout;      // bit k: lane k is alpha-tested
  std::uint8_t unused[9];
};
static_assert(sizeof(LeafHeader) == 16);
inline constexpr int kLeafHeaderFloats = 4;

/// Floats a leaf of `count` triangles takes in Bvh::leaf_floats: its header and rows.
[[nodiscard]] constexpr int leaf_floats_of(int count) { return kLeafHeaderFloats + kLeafRows * leaf_width(count); }

/// Eight lanes of rows of its own: a leaf gathered from the triangles of several (the occluder
/// cache, bvh/traverse-inl.h).
struct alignas(32) LeafLanes {
  float rows[kLeafRows * LeafBlock::kLanes];
  [[nodiscard]] LeafBlock view(std::uint32_t two_sided, std::uint32_t cutout, std::uint32_t count) const {
    return LeafBlock{rows, LeafBlock::kLanes, two_sided, cutout, 0, count};
  }
};

struct BvhOptions {
  int branching = 4;     // 2 or 4 children per node (Embree's maxBranchingFactor)
  int max_leaf_size = 8; // triangles per leaf, 1-8 (paper Sec. 6)
};

/// Checks both fields; the error names the field ("bvh.branching") and its value.
[[nodiscard]] Result<void> check_options(const BvhOptions& options);

struct Bvh {
  std::vector<Node, DefaultInitAllocator<Node>> nodes;  // nodes[0] is the root
  // The triangles are numbered in leaf order (a leaf's are contiguous). Their floats live in the
  // leaves only: each a LeafHeader then its rows, back to back, in node order.
  std::vector<float, DefaultInitAllocator<float, lut::CacheLineAllocator<float>>> leaf_floats;
  std::size_t leaf_count = 0;
  std::vector<std::uint32_t> scene_triangle;   // per triangle: its index in the scene
  std::vector<std::uint32_t> object;           // per triangle: Scene::object; empty when every one is 0
  /// The scene's cut-outs when any triangle is alpha-tested (LeafBlock::cutout), else null.
  std::shared_ptr<const Cutouts> cutouts;
  float largest_coordinate = 0.0f;             // max |coordinate| of every vertex (the grazing margin's scale)
  float box_shrink_for_test = 0.0f;            // world units off the box cull's margin: a test's too-tight cull

  [[nodiscard]] std::size_t triangle_count() const { return scene_triangle.size(); }
  [[nodiscard]] std::uint32_t object_of(std::uint32_t t) const { return object.empty() ? 0u : object[t]; }
  /// The leaf at `place` in leaf_floats (Node::child of a leaf slot).
  [[nodiscard, gnu::always_inline]] LeafBlock leaf_at(std::uint32_t place) const {
    LeafHeader header{};
    std::memcpy(&header, leaf_floats.data() + place, sizeof header);
    return LeafBlock{leaf_floats.data() + place + kLeafHeaderFloats, leaf_width(header.count), header.two_sided,
                     header.cutout, header.first, header.count};
  }

  /// Builds over `triangles` (copied into the leaf blocks: the floats are the same, so every mask
  /// equals brute's). Fails on an empty set, or a tree deeper than 64 levels (millions of
  /// triangles with one centroid). Multithreaded (TBB); `progress` gets (done, total) work units.
  [[nodiscard]] static Result<Bvh> build(const lut::TriangleSet& triangles, const BvhOptions& options = {},
                                         const ProgressCallback& progress = {});
  /// The same tree and floats from the scene directly, without a TriangleSet (53 bytes a
  /// triangle fewer at the peak): the spheres are computed as TriangleSet::build computes them.
  [[nodiscard]] static Result<Bvh> build(const Scene& scene, const BvhOptions& options = {},
                                         const ProgressCallback& progress = {});
  /// The same tree, freeing the scene's arrays (scene = Scene{}, on success or failure after the
  /// topology) once the leaf blocks are made, before the node spheres.
  [[nodiscard]] static Result<Bvh> build(Scene&& scene, const BvhOptions& options = {},
                                         const ProgressCallback& progress = {});

  /// Refit after a deformation: `vertices` are the triangles build was given (3 per triangle,
  /// in the scene's order; sidedness, objects and cut-outs kept), at new positions. The tree keeps its topology; every box
  /// and sphere and the leaf blocks' floats are recomputed bottom-up from the new
  /// triangles, as conservative as build's, so the masks are brute's bit for bit as after a fresh
  /// build (only the culling's speed may drop when triangles move far from their old
  /// neighbours). Single-threaded, linear in the size.
  void refit(std::span<const glm::vec3> vertices);
};

/// What a BVH holds, in bytes by array (capacities: what the process pays for them).
struct BvhBytes {
  std::size_t nodes = 0;    // Node, 184 bytes each
  std::size_t leaves = 0;   // the leaves' headers and rows: 120, 224 or 432 bytes a leaf (up to 2, 4, 8 triangles)
  std::size_t indices = 0;  // scene_triangle and object (when kept), 4 bytes a triangle each
  [[nodiscard]] std::size_t total() const { return nodes + leaves + indices; }
};
[[nodiscard]] BvhBytes memory_bytes(const Bvh& bvh);

/// The lanes of a leaf (bit k: triangle first + k, k < count) that belong to `object`: the
/// triangles a receiver excluding it skips (Receiver::excluded_object).
[[nodiscard]] inline std::uint32_t object_lanes(const Bvh& bvh, std::uint32_t first, int count, std::uint32_t object) {
  std::uint32_t lanes = 0;
  for (int k = 0; k < count; ++k) lanes |= static_cast<std::uint32_t>(bvh.object_of(first + static_cast<std::uint32_t>(k)) == object) << k;
  return lanes;
}

/// Lane `l` of a leaf block as the mask kernels take one triangle (lut/kernels-inl.h): the same
/// floats and flags; the object is left 0 (the traversal reads Bvh::object_of).
[[nodiscard]] inline lut::PackedTriangle block_triangle(const LeafBlock& block, int l) {
  lut::PackedTriangle p;
  p.v0 = {block.v0x()[l], block.v0y()[l], block.v0z()[l]};
  p.v1 = {block.v1x()[l], block.v1y()[l], block.v1z()[l]};
  p.v2 = {block.v2x()[l], block.v2y()[l], block.v2z()[l]};
  p.centre = {block.cx()[l], block.cy()[l], block.cz()[l]};
  p.radius = block.radius()[l];
  p.two_sided = (block.two_sided >> l) & 1u;
  p.cutout = (block.cutout >> l) & 1u;
  return p;
}

}  // namespace exao::bvh
