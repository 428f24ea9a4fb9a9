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

// The receiver's rays as world-space segments o + t e_i, t in [0, 1] (e_i = r R p_i, p_i the
// sample's end point in the receiver frame), for the box test of a node's children: the
// reciprocals of e_i, a cluster at a time when first needed. A component below 1e-30 is nudged
// to 1e-30, so that no product below is 0 * inf (the slab then holds the ray iff it holds o,
// as for a zero component).
template <int Bits>
struct WorldRays {
  alignas(64) float ix[Bits], iy[Bits], iz[Bits];
  std::uint64_t ready = 0;  // bit k: cluster k is computed
};

template <int Bits>
inline void prepare_world_rays(const SampleArrays& s, const Frame& f, float r, std::uint64_t clusters,
                               WorldRays<Bits>& out) {
  using L = Lanes;
  const auto tiny = L::set(1e-30f), one = L::set(1.0f);
  const auto nudge = [&](typename L::F e) { return L::select(L::lt(L::abs(e), tiny), tiny, e); };
  for (std::uint64_t todo = clusters & ~out.ready; todo; todo &= todo - 1) {
    const int k = std::countr_zero(todo);
    for (int j = 0; j < kSampleCluster; j += L::kWidth) {
      const int i = kSampleCluster * k + j;
      const auto px = L::mul(L::load(s.px() + i), L::set(r)), py = L::mul(L::load(s.py() + i), L::set(r)),
                 pz = L::mul(L::load(s.pz() + i), L::set(r));
      const auto world = [&](const glm::vec3& t, const glm::vec3& b, const glm::vec3& n, int c) {
        return L::add(L::add(L::mul(px, L::set(t[c])), L::mul(py, L::set(b[c]))), L::mul(pz, L::set(n[c])));
      };
      L::store(out.ix + i, L::div(one, nudge(world(f.tangent, f.bitangent, f.normal, 0))));
      L::store(out.iy + i, L::div(one, nudge(world(f.tangent, f.bitangent, f.normal, 1))));
      L::store(out.iz + i, L::div(one, nudge(world(f.tangent, f.bitangent, f.normal, 2))));
    }
  }
  out.ready |= clusters;
}

// The rays of `clusters` whose segment meets child k's box grown by `grow` (world units): the
// slab test. A cull only: grow covers the rounding of the frame, of the triangles' plane tests
// and of these products (a few ulps of the coordinates, far below grow), so a ray that meets a
// triangle of the child meets the grown box.
template <int Bits>
[[nodiscard]] inline Mask<Bits> box_mask(const Node& node, int k, const glm::vec3& o, float grow,
                                         const WorldRays<Bits>& rays, std::uint64_t clusters) {
  using L = Lanes;
  const auto lx = L::set(node.lo_x[k] - grow - o.x), ly = L::set(node.lo_y[k] - grow - o.y),
             lz = L::set(node.lo_z[k] - grow - o.z);
  const auto hx = L::set(node.hi_x[k] + grow - o.x), hy = L::set(node.hi_y[k] + grow - o.y),
             hz = L::set(node.hi_z[k] + grow - o.z);
  const auto zero = L::set(0.0f), one = L::set(1.0f);
  Mask<Bits> out;
  for (; clusters; clusters &= clusters - 1) {
    const int c = std::countr_zero(clusters);
    std::uint64_t bits = 0;
    for (int j = 0; j < kSampleCluster; j += L::kWidth) {
      const int i = kSampleCluster * c + j;
      const auto ix = L::load(rays.ix + i), iy = L::load(rays.iy + i), iz = L::load(rays.iz + i);
      const auto x0 = L::mul(lx, ix), x1 = L::mul(hx, ix);
      const auto y0 = L::mul(ly, iy), y1 = L::mul(hy, iy);
      const auto z0 = L::mul(lz, iz), z1 = L::mul(hz, iz);
      const auto enter = L::max(L::max(L::min(x0, x1), L::min(y0, y1)), L::max(L::min(z0, z1), zero));
      const auto exit = L::min(L::min(L::max(x0, x1), L::max(y0, y1)), L::min(L::max(z0, z1), one));
      bits |= L::bits(L::le(enter, exit)) << j;
    }
    out.words[c * kSampleCluster / 64] |= bits << (c * kSampleCluster % 64);
  }
  return out;
}

// The clusters of `open` that child k's sphere can reach (all when the receiver is inside it).
template <int Bits>
[[nodiscard]] inline std::uint64_t child_clusters(const KernelContext& ctx, const ChildSetup& children, int k,
                                                  std::uint64_t open, lut::KernelCounters* counters) {
  std::uint64_t clusters = open & kAllClusters<Bits>;
  const SphereTest test = children.test(k);
  if (test.kind == SphereTest::Kind::Rays && ctx.cull_clusters && test.cone_sin < 1.0f) {
    clusters &= sphere_reach<Bits>(*ctx.samples, test.axis, test.cone_cos, test.cone_sin, ctx.cluster_slack);
  }
  if (counters) counters->cluster_tests += static_cast<std::uint64_t>(std::popcount(clusters));
  return clusters;
}

// The lanes of the cached occluders [first, first + n) of `cache` (padding lanes NaN, as the
// builder's): the same floats as their own leaves' rows, so leaf_setup gives the same bits.
inline LeafBlock gather_block(const Bvh& bvh, const OccluderCache& cache, int first, int n, LeafLanes& lanes) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::uint32_t two_sided = 0, cutout = 0;
  for (int l = 0; l < LeafBlock::kLanes; ++l) {
    if (l >= n) {
      for (int r = 0; r < kLeafRows; ++r) lanes.rows[r * LeafBlock::kLanes + l] = nan;
      continue;
    }
    const LeafBlock from = bvh.leaf_at(cache.place[first + l]);
    const int k = cache.lane[first + l];
    for (int r = 0; r < kLeafRows; ++r) lanes.rows[r * LeafBlock::kLanes + l] = from.row(r)[k];
    two_sided |= ((from.two_sided >> k) & 1u) << l;
    cutout |= ((from.cutout >> k) & 1u) << l;
  }
  return lanes.view(two_sided, cutout, static_cast<std::uint32_t>(n));
}

// Lane `lane` of a leaf, as the finish steps of lut/kernels-inl.h take a triangle: its floats
// are gathered (packed_of) only when a mask survives, not for every triangle the set-up passes.
struct LaneTriangle {
  const LeafBlock* block;
  int lane;
};
[[nodiscard]] inline PackedTriangle packed_of(const LaneTriangle& tri) { return block_triangle(*tri.block, tri.lane); }

// The rest of triangle t's mask (lane l of `block`) after its set-up in lane l: pure, triangle_finish;
// certain, the sure mask of certain_finish, its maybe bits ORed into *maybe. Cut-outs keep only
// the bits their alpha decides.
template <int Bits, bool Certain>
[[nodiscard]] inline Mask<Bits> finish_triangle(const Bvh& bvh, const lut::MaskEngine& engine, const LeafBlock& block,
                                                std::uint32_t t, const LeafSetup& setup, int l, const Frame& frame,
                                                float g, std::uint64_t allowed, lut::KernelCounters* counters,
                                                Mask<Bits>& maybe) {
  const lut::KernelContext& ctx = engine.kernel_context();
  const LaneTriangle tri{&block, l};
  const bool cutout = (block.cutout >> l) & 1u;
  if constexpr (Certain) {
    CertainMasks<Bits> both = certain_finish<Bits>(ctx, tri, setup.certain(l), frame, g, allowed, counters);
    if (cutout) {
      lut::keep_cutout_sure(*bvh.cutouts, bvh.scene_triangle[t], engine.rays(), frame, both.sure.words, both.maybe.words);
    }
    maybe |= both.maybe;
    return both.sure;
  } else {
    Mask<Bits> mask = triangle_finish<Bits>(ctx, tri, setup.pure(l), frame, allowed, counters);
    if (cutout) lut::keep_cutout_hits(*bvh.cutouts, bvh.scene_triangle[t], engine.rays(), frame, mask.words);
    return mask;
  }
}

// Before the traversal: the masks of the triangles that blocked new rays at the previous
// receiver (OccluderCache), set up eight at a time in lanes. Neighbouring receivers are mostly
// blocked by the same triangles, so the cumulative mask starts nearly complete and the traversal
// then culls every node and cluster behind them. Each is a triangle's own mask, computed as the
// traversal computes it, so blocked holds only bits the answer holds and every cull stays
// conservative; the traversal still meets each of them again (and adds nothing). Returns the
// triangles set up.
template <int Bits, bool Certain>
inline int mask_cached_occluders(const Bvh& bvh, const lut::MaskEngine& engine, const Frame& frame, float g,
                                 const OccluderCache& previous, OccluderCache& next, Mask<Bits>& blocked,
                                 Mask<Bits>& maybe, lut::KernelCounters* counters) {
  const int n_rays = engine.samples();
  std::uint64_t allowed = lut::open_clusters(blocked, n_rays);
  for (int first = 0; first < previous.count && allowed; first += LeafBlock::kLanes) {
    const int n = std::min(LeafBlock::kLanes, previous.count - first);
    LeafLanes lanes;
    const LeafBlock block = gather_block(bvh, previous, first, n, lanes);
    LeafSetup setup;
    std::uint32_t live = leaf_setup<Certain>(engine.kernel_context(), block, frame, g, setup) & ((1u << n) - 1u);
    for (; live && allowed; live &= live - 1) {
      const int l = std::countr_zero(live);
      const std::uint32_t t = bvh.leaf_at(previous.place[first + l]).first + previous.lane[first + l];
      if (frame.excluded_object != kNoObject && bvh.object_of(t) == frame.excluded_object) continue;
      const Mask<Bits> sure =
          finish_triangle<Bits, Certain>(bvh, engine, block, t, setup, l, frame, g, allowed, counters, maybe);
      if (popcount_and_not(sure, blocked) == 0) continue;
      blocked |= sure;
      allowed &= lut::open_clusters(blocked, n_rays);
      next.add(previous.place[first + l], previous.lane[first + l]);
    }
  }
  return previous.count;
}

// The margins of one receiver's world-space culls.
struct ReceiverMargins {
  float g = 0.0f;         // certain: 2 delta of core/grazing.h, world units
  float slack = 0.0f;     // float slack of the box culls (at least 2 g for certain)
  float reach2 = 0.0f;    // (r + slack)^2: a child box farther than this is culled
  float box_grow = 0.0f;  // the box masks' margin
};

template <bool Certain>
[[nodiscard]] inline ReceiverMargins receiver_margins(const Bvh& bvh, const lut::MaskEngine& engine, const Frame& frame) {
  const float r = engine.kernel_context().radius;
  const glm::vec3 o = frame.origin;
  ReceiverMargins m;
  // Float slack for the world-space tests, which triangle_mask computes differently.
  m.slack = engine.reach_slack(o, 0.0f);
  // Certain: g = 2 delta, delta from the largest coordinate of the origin and of the whole
  // scene (an upper bound of every triangle's), rounded up.
  if constexpr (Certain) {
    const float largest = std::max({std::abs(o.x), std::abs(o.y), std::abs(o.z), bvh.largest_coordinate});
    m.g = static_cast<float>(2.0 * kGrazingUlps * 0x1p-24) * (largest + r) * (1.0f + 1e-3f);
    m.slack = std::max(m.slack, 2.0f * m.g);
  }
  m.reach2 = (r + m.slack) * (r + m.slack);
  // The boxes' margin covers the rounding of the frame and of the plane tests.
  m.box_grow = 2e-5f * (bvh.largest_coordinate + r) + m.slack - bvh.box_shrink_for_test;
  return m;
}

// What one receiver's traversal has found so far.
template <int Bits>
struct ReceiverState {
  Mask<Bits> blocked;     // the cumulative mask
  Mask<Bits> maybe;       // certain: the maybe bits met
  std::uint32_t units = 0;  // certain: the work spent (nodes and leaf triangles)
  OccluderCache next;     // the triangles that blocked new rays, for the next receiver
};

// Culls and estimates the children of `node`, and pushes the survivors, largest estimate on top.
// Node masks come from the children's boxes where every triangle mask lies in its box (exact
// planes; certain masks grown by g < slack); a table's masks carry its cells' errors, and only
// the sphere holds them (lut/sphere_test.h).
template <int Bits, bool Certain>
[[gnu::always_inline]] inline void push_children(const lut::KernelContext& ctx, const Node& node, const Frame& frame,
                          const ReceiverMargins& m, const Mask<Bits>& blocked, int n_rays, WorldRays<Bits>& world_rays,
                          detail::StackEntry<Bits>* stack, int& top, lut::KernelCounters* counters) {
  const std::uint64_t open = lut::open_clusters(blocked, n_rays);
  int estimate[kMaxChildren];
  Mask<Bits> child_mask[kMaxChildren];
  int order[kMaxChildren];
  int survivors = 0;
  ChildSetup children;
  for (std::uint32_t live = child_setup(node, frame, m.reach2, m.slack, m.g, ctx.radius, children); live;
       live &= live - 1) {
    const int k = std::countr_zero(live);
    if (ctx.exact || Certain) {
      // The open clusters the cone of the child's sphere reaches, then the rays of those that
      // meet its box: tighter than the sphere's own rays where the child is flat or long (most
      // of a mesh), and cheaper.
      const std::uint64_t wanted = child_clusters<Bits>(ctx, children, k, open, counters);
      if (!wanted) continue;
      prepare_world_rays<Bits>(*ctx.samples, frame, ctx.radius, wanted, world_rays);
      child_mask[k] = box_mask<Bits>(node, k, frame.origin, m.box_grow, world_rays, wanted);
    } else {
      child_mask[k] = sphere_test_mask<Bits>(ctx, children.test(k), open, counters);
    }
    estimate[k] = popcount_and_not(child_mask[k], blocked);
    if (estimate[k] == 0) continue;
    order[survivors++] = k;
  }
  // Push in increasing order, so the largest is popped next (insertion sort: at most four).
  for (int i = 1; i < survivors; ++i) {
    for (int j = i; j > 0 && estimate[order[j]] < estimate[order[j - 1]]; --j) std::swap(order[j], order[j - 1]);
  }
  for (int i = 0; i < survivors; ++i) {
    const int k = order[i];
    stack[top++] = {child_mask[k], node.child[k], node.leaf_size[k]};
  }
}

// The leaf at `place` (a leaf slot's Node::child) of `size` triangles, on the clusters of
// `wanted`: its set-up in lanes, then the rest for the triangles that pass, in order, until no
// cluster is left open.
template <int Bits, bool Stats, bool Certain>
[[gnu::always_inline]] inline void mask_leaf(const Bvh& bvh, const lut::MaskEngine& engine, const Frame& frame, float g, std::uint32_t place,
                      int size, const Mask<Bits>& wanted, ReceiverState<Bits>& state, TraversalStats* stats) {
  const lut::KernelContext& ctx = engine.kernel_context();
  lut::KernelCounters* counters = Stats ? &stats->kernels : nullptr;
  const int n_rays = engine.samples();
  std::uint64_t allowed = lut::occupied_clusters(wanted);
  LeafSetup setup;
  const LeafBlock block = bvh.leaf_at(place);
  const std::uint32_t first = block.first;
  std::uint32_t live = leaf_setup<Certain>(ctx, block, frame, g, setup);
  if (frame.excluded_object != kNoObject) live &= ~object_lanes(bvh, first, size, frame.excluded_object);
  if constexpr (Stats) stats->triangles_tested += static_cast<std::uint64_t>(size);
  for (; live; live &= live - 1) {
    const int l = std::countr_zero(live);
    const Mask<Bits> sure =
        finish_triangle<Bits, Certain>(bvh, engine, block, first + l, setup, l, frame, g, allowed, counters, state.maybe);
    const bool blocks = popcount_and_not(sure, state.blocked) > 0;
    if constexpr (Stats) stats->triangles_blocking += blocks;
    if (!blocks) continue;
    state.next.add(place, l);
    state.blocked |= sure;
    allowed &= lut::open_clusters(state.blocked, n_rays);
    if (!allowed) break;
  }
}

template <int Bits, bool Stats, bool Certain>
[[nodiscard]] Mask<Bits> traverse_receiver(const Bvh& bvh, const lut::MaskEngine& engine, const Frame& frame,
                                           TraversalStats* stats, const MaskBudget* budget,
                                           HybridOutcome<Bits>* outcome, OccluderCache* cache) {
  const lut::KernelContext& ctx = engine.kernel_context();
  lut::KernelCounters* counters = Stats ? &stats->kernels : nullptr;
  const Mask<Bits> all = engine.template all_rays<Bits>();
  const ReceiverMargins m = receiver_margins<Certain>(bvh, engine, frame);
  ReceiverState<Bits> state;
  WorldRays<Bits> world_rays;
  // The cost model (Certain, with a budget): stop when the work spent, in Embree rays, exceeds
  // the rays decided so far plus the allowance.
  const auto over_budget = [&]() {
    if constexpr (!Certain) {
      return false;
    } else {
      if (!budget) return false;
      const float spent = static_cast<float>(state.units) * budget->rays_per_unit;
      return spent > budget->allowance && spent > static_cast<float>(state.blocked.popcount()) + budget->allowance;
    }
  };
  const auto finish = [&](bool complete) {
    if constexpr (Certain) {
      outcome->units = state.units;
      outcome->complete = complete;
      outcome->undecided = complete ? and_not(state.maybe, state.blocked) : and_not(all, state.blocked);
    }
    if (cache) *cache = state.next;
    return state.blocked;
  };

  // The occluders of the previous receiver first; this receiver's, for the next.
  if (cache && cache->count > 0) {
    const int set_up = mask_cached_occluders<Bits, Certain>(bvh, engine, frame, m.g, *cache, state.next, state.blocked,
                                                            state.maybe, counters);
    if constexpr (Stats) stats->triangles_cached += static_cast<std::uint64_t>(set_up);
    if constexpr (Certain) state.units += static_cast<std::uint32_t>(set_up);
  }

  alignas(64) detail::StackEntry<Bits> stack[detail::kStackSize];
  int top = 0;
  std::uint32_t node_index = 0;
  if constexpr (Stats) ++stats->receivers;
  while (true) {
    if constexpr (Stats) ++stats->nodes_visited;
    if constexpr (Certain) {
      ++state.units;
      if (over_budget()) return finish(false);
    }
    push_children<Bits, Certain>(ctx, bvh.nodes[node_index], frame, m, state.blocked, engine.samples(), world_rays,
                                 stack, top, counters);
    // Pop until an internal node is found, masking leaves on the way.
    bool descended = false;
    while (top > 0) {
      const detail::StackEntry<Bits>& entry = stack[--top];
      const Mask<Bits> wanted = and_not(entry.mask, state.blocked);
      if (wanted.none()) continue;  // blocked meanwhile
      if (entry.leaf_size == 0) {
        node_index = entry.child;
        descended = true;
        break;
      }
      mask_leaf<Bits, Stats, Certain>(bvh, engine, frame, m.g, entry.child, entry.leaf_size, wanted, state, stats);
      if (state.blocked == all) return finish(true);
      if constexpr (Certain) {
        state.units += entry.leaf_size;
        if (over_budget()) return finish(false);
      }
    }
    if (!descended) return finish(true);
  }
}

template <int Bits>
void leaf_masks(const Bvh& bvh, const lut::MaskEngine& engine, const Frame& frame, std::uint32_t place, int count,
                std::uint64_t allowed, Mask<Bits>* out) {
  const lut::KernelContext& ctx = engine.kernel_context();
  const LeafBlock block = bvh.leaf_at(place);
  LeafSetup setup;
  const std::uint32_t live = leaf_setup<false>(ctx, block, frame, 0.0f, setup);
  for (int l = 0; l < count; ++l) {
    out[l] = (live >> l) & 1u ? triangle_finish<Bits>(ctx, LaneTriangle{&block, l}, setup.pure(l), frame, allowed, nullptr)
                              : Mask<Bits>{};
  }
}
