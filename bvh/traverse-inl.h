// The BVH traversal of bvh/traverse.h for one instruction set, with the mask kernels inline.
// Included by bvh/traverse_isa.cpp inside namespace EXAO_KERNEL_NS, after lut/kernels-inl.h.
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

// Steps 1-4 of the certain kernels (lut/kernels-inl.h, CertainSetup) for every triangle of a
// leaf at once, lane = triangle, in the expressions of Frame::to_local and glm (dot is
// (x + y) + z, cross the usual three differences). Returns the lanes that pass; their set-up is
// in `out` (struct of arrays).
struct alignas(32) CertainBlock {
  float ax[8], ay[8], az[8], bx[8], by[8], bz[8], cx[8], cy[8], cz[8];
  float nx[8], ny[8], nz[8], ux[8], uy[8], uz[8], sd[8], ox[8], oy[8], oz[8];

  [[nodiscard]] CertainSetup lane(int l) const {
    return {{ax[l], ay[l], az[l]}, {bx[l], by[l], bz[l]}, {cx[l], cy[l], cz[l]},
            {nx[l], ny[l], nz[l]}, {ux[l], uy[l], uz[l]}, sd[l], {ox[l], oy[l], oz[l]}};
  }
};

[[nodiscard]] inline std::uint32_t certain_setup_block(const KernelContext& ctx, const LeafBlock& leaf,
                                                       const Frame& frame, float g_world, CertainBlock& out) {
  using L = Lanes8;
  const auto ox = L::set(frame.origin.x), oy = L::set(frame.origin.y), oz = L::set(frame.origin.z);
  const auto tx = L::set(frame.tangent.x), ty = L::set(frame.tangent.y), tz = L::set(frame.tangent.z);
  const auto bx = L::set(frame.bitangent.x), by = L::set(frame.bitangent.y), bz = L::set(frame.bitangent.z);
  const auto nx = L::set(frame.normal.x), ny = L::set(frame.normal.y), nz = L::set(frame.normal.z);
  const auto inv_r = L::set(ctx.inv_radius);
  const float g_n = g_world * ctx.inv_radius;
  const auto g = L::set(g_n), minus_gw = L::set(-g_world), zero = L::set(0.0f);
  const auto d_max = L::set(1.0f + g_n), big = L::set(std::numeric_limits<float>::max());
  const auto reach = L::set(ctx.radius + g_world);
  std::uint32_t live = 0;
  for (int l = 0; l < 8; l += L::kWidth) {
    // 1. Into the receiver frame: to_local is dot(v - o, t), dot(v - o, b), dot(v - o, n).
    const auto local = [&](const float* x, const float* y, const float* z, auto& lx, auto& ly, auto& lz) {
      const auto dx = L::sub(L::load(x + l), ox), dy = L::sub(L::load(y + l), oy), dz = L::sub(L::load(z + l), oz);
      lx = L::add(L::add(L::mul(dx, tx), L::mul(dy, ty)), L::mul(dz, tz));
      ly = L::add(L::add(L::mul(dx, bx), L::mul(dy, by)), L::mul(dz, bz));
      lz = L::add(L::add(L::mul(dx, nx), L::mul(dy, ny)), L::mul(dz, nz));
    };
    typename L::F ax, ay, az, bx_, by_, bz_, cx, cy, cz, ccx, ccy, ccz;
    local(leaf.v0x, leaf.v0y, leaf.v0z, ax, ay, az);
    local(leaf.v1x, leaf.v1y, leaf.v1z, bx_, by_, bz_);
    local(leaf.v2x, leaf.v2y, leaf.v2z, cx, cy, cz);
    auto ok = L::not_(L::both(L::both(L::le(az, minus_gw), L::le(bz_, minus_gw)), L::le(cz, minus_gw)));
    ax = L::mul(ax, inv_r), ay = L::mul(ay, inv_r), az = L::mul(az, inv_r);
    bx_ = L::mul(bx_, inv_r), by_ = L::mul(by_, inv_r), bz_ = L::mul(bz_, inv_r);
    cx = L::mul(cx, inv_r), cy = L::mul(cy, inv_r), cz = L::mul(cz, inv_r);
    // 3. n = cross(b - a, c - a), |n|, the unit normal and the signed distance.
    const auto ex = L::sub(bx_, ax), ey = L::sub(by_, ay), ez = L::sub(bz_, az);
    const auto fx = L::sub(cx, ax), fy = L::sub(cy, ay), fz = L::sub(cz, az);
    const auto n_x = L::sub(L::mul(ey, fz), L::mul(fy, ez));
    const auto n_y = L::sub(L::mul(ez, fx), L::mul(fz, ex));
    const auto n_z = L::sub(L::mul(ex, fy), L::mul(fx, ey));
    const auto n_length = L::sqrt(L::add(L::add(L::mul(n_x, n_x), L::mul(n_y, n_y)), L::mul(n_z, n_z)));
    ok = L::both(ok, L::both(L::gt(n_length, zero), L::le(n_length, big)));
    const auto ux = L::div(n_x, n_length), uy = L::div(n_y, n_length), uz = L::div(n_z, n_length);
    const auto sd = L::add(L::add(L::mul(ux, ax), L::mul(uy, ay)), L::mul(uz, az));
    const auto d = L::abs(sd);
    ok = L::both(ok, L::le(d, d_max));
    // 2. Facing (one-sided lanes, away from the plane): dot(n, -a) > 0.
    const auto facing = L::gt(L::add(L::add(L::mul(n_x, L::sub(zero, ax)), L::mul(n_y, L::sub(zero, ay))),
                                     L::mul(n_z, L::sub(zero, az))),
                              zero);
    const auto two_sided = L::from_bits(leaf.two_sided >> l);
    ok = L::both(ok, L::either(L::either(L::lt(d, g), two_sided), facing));
    // 4. The influence sphere.
    local(leaf.cx, leaf.cy, leaf.cz, ccx, ccy, ccz);
    const auto rr = L::add(L::load(leaf.radius + l), reach);
    ok = L::both(ok, L::le(L::add(L::add(L::mul(ccx, ccx), L::mul(ccy, ccy)), L::mul(ccz, ccz)), L::mul(rr, rr)));
    live |= static_cast<std::uint32_t>(L::bits(ok)) << l;
    L::store(out.ax + l, ax), L::store(out.ay + l, ay), L::store(out.az + l, az);
    L::store(out.bx + l, bx_), L::store(out.by + l, by_), L::store(out.bz + l, bz_);
    L::store(out.cx + l, cx), L::store(out.cy + l, cy), L::store(out.cz + l, cz);
    L::store(out.nx + l, n_x), L::store(out.ny + l, n_y), L::store(out.nz + l, n_z);
    L::store(out.ux + l, ux), L::store(out.uy + l, uy), L::store(out.uz + l, uz);
    L::store(out.sd + l, sd);
    L::store(out.ox + l, ccx), L::store(out.oy + l, ccy), L::store(out.oz + l, ccz);
  }
  return live;
}

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
  const glm::vec3 n = frame.normal;
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
      child_mask[k] = region_mask<Bits>(ctx, centre, node.radius[k] + g, lut::kNodeMargin, open, counters);
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
      if constexpr (Certain) {
        // The leaf's set-up in lanes, then the planes of the triangles that pass, in order.
        CertainBlock setup;
        std::uint32_t live = certain_setup_block(ctx, bvh.blocks[bvh.leaf_block[entry.child]], frame, g, setup);
        if (frame.excluded_object != kNoObject) live &= ~object_lanes(bvh, entry.child, entry.leaf_size, frame.excluded_object);
        if constexpr (Stats) stats->triangles_tested += entry.leaf_size;
        while (live) {
          const int l = std::countr_zero(live);
          live &= live - 1;
          const CertainMasks<Bits> both =
              certain_finish<Bits>(ctx, bvh.packed[entry.child + l], setup.lane(l), frame, g, allowed, counters);
          if constexpr (Stats) {
            if (popcount_and_not(both.sure, blocked) > 0) ++stats->triangles_blocking;
          }
          maybe |= both.maybe;
          if (both.sure.none()) continue;
          blocked |= both.sure;
          allowed &= lut::open_clusters(blocked, n_rays);
          if (!allowed) break;
        }
      } else {
        for (std::uint32_t t = entry.child; t < entry.child + entry.leaf_size; ++t) {
          if (bvh.packed[t].object == frame.excluded_object) continue;  // Receiver::excluded_object
          const Mask<Bits> m = triangle_mask<Bits>(ctx, bvh.packed[t], frame, allowed, counters);
          if constexpr (Stats) {
            ++stats->triangles_tested;
            if (popcount_and_not(m, blocked) > 0) ++stats->triangles_blocking;
          }
          if (m.none()) continue;
          blocked |= m;
          allowed &= lut::open_clusters(blocked, n_rays);
          if (!allowed) break;
        }
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
