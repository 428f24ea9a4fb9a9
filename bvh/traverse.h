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
//  - traversal stops when every ray is blocked.

#include <algorithm>
#include <cstdint>

#include "bvh/bvh.h"
#include "core/mask.h"
#include "core/receiver_frame.h"
#include "lut/mask_engine.h"

namespace exao::bvh {

/// Work counters of one or more traversals.
struct TraversalStats {
  std::uint64_t receivers = 0;
  std::uint64_t nodes_visited = 0;       // internal nodes whose children were tested
  std::uint64_t triangles_tested = 0;    // triangle_mask calls
  std::uint64_t triangles_blocking = 0;  // triangles that blocked at least one new ray

  TraversalStats& operator+=(const TraversalStats& o) {
    receivers += o.receivers;
    nodes_visited += o.nodes_visited;
    triangles_tested += o.triangles_tested;
    triangles_blocking += o.triangles_blocking;
    return *this;
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

/// The mask of the receiver whose frame is `frame`. With `Stats`, counts work into `stats`.
template <int Bits, bool Stats>
[[nodiscard]] Mask<Bits> traverse(const Bvh& bvh, const lut::MaskEngine& engine, const Frame& frame,
                                  TraversalStats* stats) {
  const float r = engine.rays().radius;
  const Mask<Bits> all = engine.template all_rays<Bits>();
  Mask<Bits> blocked;
  const glm::vec3 o = frame.origin;
  const glm::vec3 n = frame.normal;
  // Float slack for the world-space tests below, which triangle_mask computes differently.
  const float slack = engine.reach_slack(o, 0.0f);
  const float reach2 = (r + slack) * (r + slack);

  alignas(64) detail::StackEntry<Bits> stack[detail::kStackSize];
  int top = 0;
  std::uint32_t node_index = 0;
  if constexpr (Stats) ++stats->receivers;

  while (true) {
    const Node& node = bvh.nodes[node_index];
    if constexpr (Stats) ++stats->nodes_visited;

    // Cull and estimate every child of the node.
    int estimate[kMaxChildren];
    Mask<Bits> child_mask[kMaxChildren];
    int order[kMaxChildren];
    int survivors = 0;
    for (int k = 0; k < node.child_count; ++k) {
      const float dx = std::max({node.lo_x[k] - o.x, 0.0f, o.x - node.hi_x[k]});
      const float dy = std::max({node.lo_y[k] - o.y, 0.0f, o.y - node.hi_y[k]});
      const float dz = std::max({node.lo_z[k] - o.z, 0.0f, o.z - node.hi_z[k]});
      if (dx * dx + dy * dy + dz * dz > reach2) continue;
      // Highest point of the box above the tangent plane: centre height + half extents along |n|.
      const glm::vec3 mid(0.5f * (node.lo_x[k] + node.hi_x[k]), 0.5f * (node.lo_y[k] + node.hi_y[k]),
                          0.5f * (node.lo_z[k] + node.hi_z[k]));
      const glm::vec3 half(0.5f * (node.hi_x[k] - node.lo_x[k]), 0.5f * (node.hi_y[k] - node.lo_y[k]),
                           0.5f * (node.hi_z[k] - node.lo_z[k]));
      const float top_height = glm::dot(mid - o, n) + glm::dot(half, glm::abs(n));
      if (top_height < -slack) continue;
      const glm::vec3 centre = frame.to_local(glm::vec3(node.centre_x[k], node.centre_y[k], node.centre_z[k]));
      child_mask[k] = engine.template region_mask<Bits>(centre, node.radius[k], lut::kNodeMargin);
      estimate[k] = popcount_and_not(child_mask[k], blocked);
      if (estimate[k] == 0) continue;
      order[survivors++] = k;
    }
    // Largest estimate first: push in increasing order, so the largest is popped next
    // (insertion sort: at most four children).
    for (int i = 1; i < survivors; ++i) {
      for (int j = i; j > 0 && estimate[order[j]] < estimate[order[j - 1]]; --j) std::swap(order[j], order[j - 1]);
    }
    for (int i = 0; i < survivors; ++i) {
      const int k = order[i];
      stack[top++] = {child_mask[k], node.child[k], node.leaf_size[k]};
    }

    // Pop until an internal node is found, processing leaves on the way.
    bool descended = false;
    while (top > 0) {
      const detail::StackEntry<Bits>& entry = stack[--top];
      if (popcount_and_not(entry.mask, blocked) == 0) continue;  // blocked meanwhile
      if (entry.leaf_size == 0) {
        node_index = entry.child;
        descended = true;
        break;
      }
      for (std::uint32_t t = entry.child; t < entry.child + entry.leaf_size; ++t) {
        const Mask<Bits> m = engine.template triangle_mask<Bits>(bvh.triangles, t, frame);
        if constexpr (Stats) {
          ++stats->triangles_tested;
          if (popcount_and_not(m, blocked) > 0) ++stats->triangles_blocking;
        }
        blocked |= m;
      }
      if (blocked == all) return blocked;
    }
    if (!descended) return blocked;
  }
}

}  // namespace exao::bvh
