// The BVH traversal of bvh/traverse.h for one instruction set, with the mask kernels inline.
// Included by bvh/traverse_isa.cpp inside namespace EXAO_KERNEL_NS, after lut/kernels-inl.h and
// the two set-up files.
//
// Clusters: the traversal asks the kernels only for the clusters of rays that can still change
// the answer. A node's children are masked on the clusters that still have an open ray (a full
// cluster adds nothing to any estimate popcount(mask & ~blocked)); a leaf's triangles on the
// clusters where the leaf's own mask still has an open ray (every triangle mask below lies inside
// the leaf's mask: the nesting of lut/sphere_test.h). Since blocked only grows, what was full or
// outside the leaf's mask when the mask was computed stays irrelevant when it is used.

// Two modes, one loop (template parameter Certain):
//  - pure (the paper's method, `bvh`): the cumulative mask ORs triangle_mask, bit for bit brute's;
//  - certain (`auto`): the cumulative mask ORs the *sure* masks of certain_finish, the rays the
//    *maybe* masks add are collected as undecided, and a MaskBudget stops the masks when they
//    no longer pay: the caller casts the undecided rays (every open ray of a stopped receiver)
//    with Embree (bvh/hybrid.h). Node spheres are grown by g, as the triangles' are, so that a
//    node's mask still holds every maybe bit below it (the nesting of lut/sphere_test.h holds for
//    spheres grown by the same length), and the box culls use a slack of at least g.
// Both set up a node's children (bvh/node_setup-inl.h) and a leaf's triangles
// (bvh/leaf_setup-inl.h) in lanes, then finish the survivors one by one.

template <int Bits, bool Stats, bool Certain>
[[nodiscard]] Mask<Bits> traverse_receiver(const Bvh& bvh, const lut::MaskEngine& engine, const Frame& frame,
                                           TraversalStats* stats, const MaskBudget* budget,
                                           HybridOutcome<Bits>* outcome) {
  const lut::KernelContext& ctx = engine.kernel_context();
  lut::KernelCounters* counters = Stats ? &stats->kernels : nullptr;
  const int n_rays = engine.samples();
  const float r = ctx.radius;
  const Mask<Bits> all = engine.template all_rays<Bits>();
  Mask<Bits> blocked;
  const glm::vec3 o = frame.origin;
  // Float slack for the world-space tests below, which triangle_mask computes differently.
  float slack = engine.reach_slack(o, 0.0f);
  // Certain: g = 2 delta of core/grazing.h, delta from the largest coordinate of the origin and
  // of the whole scene (an upper bound of every triangle's), rounded up.
  float g = 0.0f;
  if constexpr (Certain) {
    const float largest = std::max({std::abs(o.x), std::abs(o.y), std::abs(o.z), bvh.largest_coordinate});
    g = static_cast<float>(2.0 * kGrazingUlps * 0x1p-24) * (largest + r) * (1.0f + 1e-3f);
    slack = std::max(slack, 2.0f * g);
  }
  const float reach2 = (r + slack) * (r + slack);
  [[maybe_unused]] Mask<Bits> maybe;
  [[maybe_unused]] std::uint32_t units = 0;
  [[maybe_unused]] const float rays_per_unit = budget ? budget->rays_per_unit : 0.0f;
  [[maybe_unused]] const float allowance = budget ? budget->allowance : 0.0f;
  // The cost model (Certain, with a budget): stop when the work spent, in Embree rays, exceeds
  // the rays decided so far plus the allowance.
  const auto over_budget = [&]() {
    if constexpr (!Certain) {
      return false;
    } else {
      if (!budget) return false;
      const float spent = static_cast<float>(units) * rays_per_unit;
      return spent > allowance && spent > static_cast<float>(blocked.popcount()) + allowance;
    }
  };
  const auto finish = [&](bool complete) {
    if constexpr (Certain) {
      outcome->units = units;
      outcome->complete = complete;
      outcome->undecided = complete ? and_not(maybe, blocked) : and_not(all, blocked);
    }
    return blocked;
  };

  alignas(64) detail::StackEntry<Bits> stack[detail::kStackSize];
  int top = 0;
  std::uint32_t node_index = 0;
  if constexpr (Stats) ++stats->receivers;

  while (true) {
    const Node& node = bvh.nodes[node_index];
    if constexpr (Stats) ++stats->nodes_visited;
    if constexpr (Certain) {
      ++units;
      if (over_budget()) return finish(false);
    }
    const std::uint64_t open = lut::open_clusters(blocked, n_rays);

    // Cull and estimate every child of the node.
    int estimate[kMaxChildren];
    Mask<Bits> child_mask[kMaxChildren];
    int order[kMaxChildren];
    int survivors = 0;
    ChildSetup children;
    for (std::uint32_t live = child_setup(node, frame, reach2, slack, g, r, children); live; live &= live - 1) {
      const int k = std::countr_zero(live);
      child_mask[k] = sphere_test_mask<Bits>(ctx, children.test(k), open, counters);
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
      const Mask<Bits> wanted = and_not(entry.mask, blocked);
      if (wanted.none()) continue;  // blocked meanwhile
      if (entry.leaf_size == 0) {
        node_index = entry.child;
        descended = true;
        break;
      }
      std::uint64_t allowed = lut::occupied_clusters(wanted);
      // The leaf's set-up in lanes, then the rest for the triangles that pass, in order.
      LeafSetup setup;
      std::uint32_t live = leaf_setup<Certain>(ctx, bvh.blocks[bvh.leaf_block[entry.child]], frame, g, setup);
      if (frame.excluded_object != kNoObject) live &= ~object_lanes(bvh, entry.child, entry.leaf_size, frame.excluded_object);
      if constexpr (Stats) stats->triangles_tested += entry.leaf_size;
      while (live) {
        const int l = std::countr_zero(live);
        live &= live - 1;
        const PackedTriangle& tri = bvh.packed[entry.child + l];
        Mask<Bits> sure;
        if constexpr (Certain) {
          CertainMasks<Bits> both = certain_finish<Bits>(ctx, tri, setup.certain(l), frame, g, allowed, counters);
          if (tri.cutout) {
            lut::keep_cutout_sure(*bvh.cutouts, bvh.scene_triangle[entry.child + l], engine.rays(), frame, both.sure.words,
                                  both.maybe.words);
          }
          maybe |= both.maybe;
          sure = both.sure;
        } else {
          sure = triangle_finish<Bits>(ctx, tri, setup.pure(l), frame, allowed, counters);
          if (tri.cutout) lut::keep_cutout_hits(*bvh.cutouts, bvh.scene_triangle[entry.child + l], engine.rays(), frame, sure.words);
        }
        if constexpr (Stats) {
          if (popcount_and_not(sure, blocked) > 0) ++stats->triangles_blocking;
        }
        if (sure.none()) continue;
        blocked |= sure;
        allowed &= lut::open_clusters(blocked, n_rays);
        if (!allowed) break;
      }
      if (blocked == all) return finish(true);
      if constexpr (Certain) {
        units += entry.leaf_size;
        if (over_budget()) return finish(false);
      }
    }
    if (!descended) return finish(true);
  }
}

template <int Bits>
void leaf_masks(const Bvh& bvh, const lut::MaskEngine& engine, const Frame& frame, std::uint32_t first, int count,
                std::uint64_t allowed, Mask<Bits>* out) {
  const lut::KernelContext& ctx = engine.kernel_context();
  const LeafBlock& block = bvh.blocks[bvh.leaf_block[first]];
  LeafSetup setup;
  const std::uint32_t live = leaf_setup<false>(ctx, block, frame, 0.0f, setup);
  for (int l = 0; l < count; ++l) {
    out[l] = (live >> l) & 1u ? triangle_finish<Bits>(ctx, bvh.packed[first + l], setup.pure(l), frame, allowed, nullptr)
                              : Mask<Bits>{};
  }
}
