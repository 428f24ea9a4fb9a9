// The set-up of every triangle of a BVH leaf at once, lane = triangle (bvh::LeafBlock): steps
// 1-6a of lut's triangle_mask for the pure traversal, and the same for the certain kernels of
// `auto`. Included by bvh/traverse_isa.cpp inside namespace EXAO_KERNEL_NS, after
// lut/kernels-inl.h (so no include guard, and it includes nothing).
//
// Pure: every lane evaluates exactly the expressions of lut's triangle_setup (Frame::to_local
// is dot3<L>(v - o, axis); glm's dot is (x + y) + z; cross the usual three differences; a vector
// over a scalar divides each component; no FMA), and a lane is live exactly when triangle_setup
// returns true, so the masks that follow are the same bits as triangle_mask's, hence brute's
// (tests/triangle_mask_test.cpp checks it on every N and every level).
// Certain: the same steps with r grown by g (lut/kernels-inl.h, "Certain masks"); nothing needs
// these bits to equal anything, only to be conservative, since every ray they leave undecided is
// cast with Embree.

struct alignas(32) LeafSetup {
  static constexpr int kLanes = LeafBlock::kLanes;
  float fx[kLanes], fy[kLanes], fz[kLanes], fd[kLanes];  // the face plane
  float ex[3][kLanes], ey[3][kLanes], ez[3][kLanes];     // the edge planes (d = 0)
  float length[3][kLanes];                               // |m_e|
  float ox[kLanes], oy[kLanes], oz[kLanes];              // the sphere's centre, receiver frame, world units
  float axis_x[kLanes], axis_y[kLanes], axis_z[kLanes];  // the cone of step 6a
  float sine[kLanes], cosine[kLanes];
  float margin[3][kLanes];  // certain: the sure/maybe margins of the edge planes
  float widen[kLanes];      // certain: g / d, the edge cull's extra slack
  std::uint32_t use_cone = 0;  // bit l: lane l has a cone (set by leaf_setup)
  std::uint32_t flat = 0;      // certain: bit l: lane l decides nothing for sure

  [[nodiscard]] TriangleSetup pure(int l) const {
    TriangleSetup s;
    s.face = {{fx[l], fy[l], fz[l]}, fd[l]};
    for (int e = 0; e < 3; ++e) {
      s.edge[e] = {{ex[e][l], ey[e][l], ez[e][l]}, 0.0f};
      s.edge_length[e] = length[e][l];
    }
    s.centre = {ox[l], oy[l], oz[l]};
    s.axis = {axis_x[l], axis_y[l], axis_z[l]};
    s.sine = sine[l];
    s.cosine = cosine[l];
    s.use_cone = (use_cone >> l) & 1u;
    return s;
  }

  [[nodiscard]] CertainSetup certain(int l) const {
    CertainSetup s;
    s.face = {{fx[l], fy[l], fz[l]}, fd[l]};
    for (int e = 0; e < 3; ++e) {
      s.edge[e] = {{ex[e][l], ey[e][l], ez[e][l]}, 0.0f};
      s.edge_length[e] = length[e][l];
      s.margin[e] = margin[e][l];
    }
    s.axis = {axis_x[l], axis_y[l], axis_z[l]};
    s.cone_sin = sine[l];
    s.cone_cos = cosine[l];
    s.widen = widen[l];
    s.use_cone = (use_cone >> l) & 1u;
    s.flat = (flat >> l) & 1u;
    return s;
  }
};

// (x0, y0, z0) . (x1, y1, z1) as glm's dot: (x + y) + z. (Functions, not lambdas: a lambda
// does not take the translation unit's target pragma, and GCC then warns about its vector ABI.)
template <class L>
[[nodiscard, gnu::always_inline]] inline typename L::F dot3(typename L::F x0, typename L::F y0, typename L::F z0,
                                                            typename L::F x1, typename L::F y1, typename L::F z1) {
  return L::add(L::add(L::mul(x0, x1), L::mul(y0, y1)), L::mul(z0, z1));
}
template <class L>
[[nodiscard, gnu::always_inline]] inline typename L::F length2_3(typename L::F x, typename L::F y, typename L::F z) {
  return dot3<L>(x, y, z, x, y, z);
}

// A receiver frame in lanes, and Frame::to_local of eight points with it.
template <class L>
struct FrameLanes {
  using F = typename L::F;
  F ox, oy, oz, tx, ty, tz, bx, by, bz, nx, ny, nz;
  explicit FrameLanes(const Frame& f)
      : ox(L::set(f.origin.x)), oy(L::set(f.origin.y)), oz(L::set(f.origin.z)),
        tx(L::set(f.tangent.x)), ty(L::set(f.tangent.y)), tz(L::set(f.tangent.z)),
        bx(L::set(f.bitangent.x)), by(L::set(f.bitangent.y)), bz(L::set(f.bitangent.z)),
        nx(L::set(f.normal.x)), ny(L::set(f.normal.y)), nz(L::set(f.normal.z)) {}
};
// Lanes l.. of a leaf row of `width` floats (bvh::leaf_width): a row narrower than the lanes
// fills them with NaN above, as the lanes past a leaf's size have always been; the scalar twin
// never reads past it.
template <class L>
[[nodiscard, gnu::always_inline]] inline typename L::F load_row(const float* p, int width) {
  if constexpr (L::kWidth == 8) {
    return L::load_first(p, width);
  } else if constexpr (L::kWidth == 4) {
    return width == 2 ? L::load2(p) : L::loadu(p);
  } else {
    return L::loadu(p);
  }
}

template <class L>
[[gnu::always_inline]] inline void to_frame(const FrameLanes<L>& f, const float* x, const float* y, const float* z,
                                            int width, typename L::F& lx, typename L::F& ly, typename L::F& lz) {
  using F = typename L::F;
  const F dx = L::sub(load_row<L>(x, width), f.ox), dy = L::sub(load_row<L>(y, width), f.oy),
          dz = L::sub(load_row<L>(z, width), f.oz);
  lx = L::add(L::add(L::mul(dx, f.tx), L::mul(dy, f.ty)), L::mul(dz, f.tz));
  ly = L::add(L::add(L::mul(dx, f.bx), L::mul(dy, f.by)), L::mul(dz, f.bz));
  lz = L::add(L::add(L::mul(dx, f.nx), L::mul(dy, f.ny)), L::mul(dz, f.nz));
}

// Ericson's distance from the origin to triangle (a, b, c) in lanes: origin_triangle_distance2
// (lut/mask_kernels.h) with every Voronoi region's value computed and the first region that
// holds chosen, as its early returns choose.
template <class L>
[[nodiscard]] inline typename L::F origin_triangle_distance2_lanes(typename L::F ax, typename L::F ay, typename L::F az,
                                                                   typename L::F bx, typename L::F by, typename L::F bz,
                                                                   typename L::F cx, typename L::F cy, typename L::F cz) {
  using F = typename L::F;
  const auto zero = L::set(0.0f);
  const F abx = L::sub(bx, ax), aby = L::sub(by, ay), abz = L::sub(bz, az);
  const F acx = L::sub(cx, ax), acy = L::sub(cy, ay), acz = L::sub(cz, az);
  const F d1 = L::neg(dot3<L>(abx, aby, abz, ax, ay, az)), d2 = L::neg(dot3<L>(acx, acy, acz, ax, ay, az));
  const F d3 = L::neg(dot3<L>(abx, aby, abz, bx, by, bz)), d4 = L::neg(dot3<L>(acx, acy, acz, bx, by, bz));
  const F d5 = L::neg(dot3<L>(abx, aby, abz, cx, cy, cz)), d6 = L::neg(dot3<L>(acx, acy, acz, cx, cy, cz));
  const F vc = L::sub(L::mul(d1, d4), L::mul(d3, d2));
  const F vb = L::sub(L::mul(d5, d2), L::mul(d1, d6));
  const F va = L::sub(L::mul(d3, d6), L::mul(d5, d4));
  // The interior (the last return), then each region from the last to the first, so the first
  // that holds wins.
  const F denom = L::div(L::set(1.0f), L::add(L::add(va, vb), vc));
  const F s1 = L::mul(vb, denom), s2 = L::mul(vc, denom);
  F result = length2_3<L>(L::add(L::add(ax, L::mul(abx, s1)), L::mul(acx, s2)),
                   L::add(L::add(ay, L::mul(aby, s1)), L::mul(acy, s2)),
                   L::add(L::add(az, L::mul(abz, s1)), L::mul(acz, s2)));
  const F d43 = L::sub(d4, d3), d56 = L::sub(d5, d6);
  {
    const F t = L::div(d43, L::add(d43, d56));
    const F v = length2_3<L>(L::add(bx, L::mul(t, L::sub(cx, bx))), L::add(by, L::mul(t, L::sub(cy, by))),
                      L::add(bz, L::mul(t, L::sub(cz, bz))));
    result = L::select(L::both(L::le(va, zero), L::both(L::ge(d43, zero), L::ge(d56, zero))), v, result);
  }
  {
    const F t = L::div(d2, L::sub(d2, d6));
    const F v = length2_3<L>(L::add(ax, L::mul(t, acx)), L::add(ay, L::mul(t, acy)), L::add(az, L::mul(t, acz)));
    result = L::select(L::both(L::le(vb, zero), L::both(L::ge(d2, zero), L::le(d6, zero))), v, result);
  }
  result = L::select(L::both(L::ge(d6, zero), L::le(d5, d6)), length2_3<L>(cx, cy, cz), result);
  {
    const F t = L::div(d1, L::sub(d1, d3));
    const F v = length2_3<L>(L::add(ax, L::mul(t, abx)), L::add(ay, L::mul(t, aby)), L::add(az, L::mul(t, abz)));
    result = L::select(L::both(L::le(vc, zero), L::both(L::ge(d1, zero), L::le(d3, zero))), v, result);
  }
  result = L::select(L::both(L::ge(d3, zero), L::le(d4, d3)), length2_3<L>(bx, by, bz), result);
  result = L::select(L::both(L::le(d1, zero), L::le(d2, zero)), length2_3<L>(ax, ay, az), result);
  return result;
}

// Step 6a of the pure set-up for lanes l..l+7: the cone of the clip sphere, whose centre is
// (cx, cy, cz) in the receiver frame, world units.
template <class L>
[[gnu::always_inline]] inline void pure_cone(const LeafBlock& leaf, int l, typename L::F cx, typename L::F cy,
                                             typename L::F cz, typename L::F inv_r, LeafSetup& out) {
  using F = typename L::F;
  const F zero = L::set(0.0f), one = L::set(1.0f);
  const F cnx = L::mul(cx, inv_r), cny = L::mul(cy, inv_r), cnz = L::mul(cz, inv_r);
  const F len = L::sqrt(dot3<L>(cnx, cny, cnz, cnx, cny, cnz));
  const F grown = L::mul(L::add(L::mul(load_row<L>(leaf.radius() + l, leaf.width), inv_r), L::mul(L::set(kTriangleMargin), len)),
                         L::set(1.0f + 1e-5f));
  const F sine = L::mul(L::div(grown, len), L::set(1.0f + 1e-5f));
  const auto cone = L::both(L::gt(len, grown), L::lt(sine, L::set(0.999f)));
  L::store(out.axis_x + l, L::select(cone, L::div(cnx, len), zero));
  L::store(out.axis_y + l, L::select(cone, L::div(cny, len), zero));
  L::store(out.axis_z + l, L::select(cone, L::div(cnz, len), zero));
  L::store(out.sine + l, sine);
  L::store(out.cosine + l,
           L::select(cone, L::mul(L::sqrt(L::sub(one, L::mul(sine, sine))), L::set(1.0f - 1e-6f)), L::set(-1.0f)));
  out.use_cone |= static_cast<std::uint32_t>(L::bits(cone)) << l;
}

// Step 6a of the certain set-up: the sphere grown by g (make_sphere_test's expressions), none
// below the horizon (the lanes it culls are false in the result), all when the origin is inside,
// else a cone when narrow enough.
template <class L>
[[nodiscard, gnu::always_inline]] inline typename L::M certain_cone(const LeafBlock& leaf, int l, typename L::F cx,
                                                                    typename L::F cy, typename L::F cz, float g_world,
                                                                    LeafSetup& out) {
  using F = typename L::F;
  const F one = L::set(1.0f), big = L::set(std::numeric_limits<float>::max());
  const F len = L::sqrt(dot3<L>(cx, cy, cz, cx, cy, cz));
  const F grown = L::mul(L::add(L::add(load_row<L>(leaf.radius() + l, leaf.width), L::set(g_world)), L::mul(L::set(kTriangleMargin), len)),
                         L::set(1.0f + 1e-6f));
  const auto rays = L::both(L::both(L::le(len, big), L::le(grown, big)), L::gt(len, L::mul(grown, L::set(1.0f + 1e-6f))));
  const F sine = L::mul(L::div(grown, len), L::set(1.0f + 1e-5f));
  const auto cone = L::both(rays, L::lt(sine, L::set(0.999f)));
  L::store(out.axis_x + l, L::div(cx, len)), L::store(out.axis_y + l, L::div(cy, len));
  L::store(out.axis_z + l, L::div(cz, len));
  L::store(out.sine + l, sine);
  L::store(out.cosine + l, L::mul(L::sqrt(L::sub(one, L::mul(sine, sine))), L::set(1.0f - 1e-6f)));
  out.use_cone |= static_cast<std::uint32_t>(L::bits(cone)) << l;
  return L::not_(L::both(rays, L::lt(cz, L::neg(grown))));
}

// The corners of the triangles of lanes l..l+7 (a, b, c) in the receiver frame, in units of r.
template <class L>
struct CornerLanes {
  typename L::F ax, ay, az, bx, by, bz, cx, cy, cz;
};

// Step 1: the corners into the receiver frame. Returns the lanes with a corner above `horizon`
// (world units: 0, or -g for certain); the corners are then scaled to units of r.
template <class L>
[[nodiscard, gnu::always_inline]] inline typename L::M corners_in_frame(const FrameLanes<L>& frame, const LeafBlock& leaf,
                                                                        int l, typename L::F horizon, typename L::F inv_r,
                                                                        CornerLanes<L>& t) {
  to_frame<L>(frame, leaf.v0x() + l, leaf.v0y() + l, leaf.v0z() + l, leaf.width, t.ax, t.ay, t.az);
  to_frame<L>(frame, leaf.v1x() + l, leaf.v1y() + l, leaf.v1z() + l, leaf.width, t.bx, t.by, t.bz);
  to_frame<L>(frame, leaf.v2x() + l, leaf.v2y() + l, leaf.v2z() + l, leaf.width, t.cx, t.cy, t.cz);
  const auto above = L::not_(L::both(L::both(L::le(t.az, horizon), L::le(t.bz, horizon)), L::le(t.cz, horizon)));
  t.ax = L::mul(t.ax, inv_r), t.ay = L::mul(t.ay, inv_r), t.az = L::mul(t.az, inv_r);
  t.bx = L::mul(t.bx, inv_r), t.by = L::mul(t.by, inv_r), t.bz = L::mul(t.bz, inv_r);
  t.cx = L::mul(t.cx, inv_r), t.cy = L::mul(t.cy, inv_r), t.cz = L::mul(t.cz, inv_r);
  return above;
}

// The face plane of steps 2-3: the unit normal u of n = cross(b - a, c - a), the signed plane
// distance sd = u . a and d = |sd|.
template <class L>
struct FaceLanes {
  typename L::F ux, uy, uz, sd, d;
  typename L::M facing;  // n . -a > 0: the receiver sees the front
};

// Steps 2-3: n, the facing, |n|, the unit normal and the plane distance. Clears the lanes of
// `live` whose triangle has no normal (|n| 0, or beyond max).
template <class L>
[[nodiscard, gnu::always_inline]] inline FaceLanes<L> face_plane(const CornerLanes<L>& t, typename L::M& live) {
  using F = typename L::F;
  const F zero = L::set(0.0f), big = L::set(std::numeric_limits<float>::max());
  const F ex = L::sub(t.bx, t.ax), ey = L::sub(t.by, t.ay), ez = L::sub(t.bz, t.az);
  const F fx = L::sub(t.cx, t.ax), fy = L::sub(t.cy, t.ay), fz = L::sub(t.cz, t.az);
  const F n_x = L::sub(L::mul(ey, fz), L::mul(fy, ez));
  const F n_y = L::sub(L::mul(ez, fx), L::mul(fz, ex));
  const F n_z = L::sub(L::mul(ex, fy), L::mul(fx, ey));
  FaceLanes<L> f;
  f.facing = L::gt(dot3<L>(n_x, n_y, n_z, L::neg(t.ax), L::neg(t.ay), L::neg(t.az)), zero);
  const F n_length = L::sqrt(dot3<L>(n_x, n_y, n_z, n_x, n_y, n_z));
  live = L::both(live, L::both(L::gt(n_length, zero), L::le(n_length, big)));
  f.ux = L::div(n_x, n_length), f.uy = L::div(n_y, n_length), f.uz = L::div(n_z, n_length);
  f.sd = dot3<L>(f.ux, f.uy, f.uz, t.ax, t.ay, t.az);
  f.d = L::abs(f.sd);
  return f;
}

// Steps 2-3's culls: the lanes of `live` whose plane is kept. Pure keeps a plane that faces the
// receiver (or is two-sided) at 0 < d <= 1; certain (g_n: g in units of r) keeps d <= 1 + g, and
// also a back face within g.
template <bool Certain, class L>
[[nodiscard, gnu::always_inline]] inline typename L::M face_kept(const FaceLanes<L>& f, typename L::M two_sided,
                                                                 float g_n, typename L::M live) {
  if constexpr (Certain) {
    live = L::both(live, L::le(f.d, L::set(1.0f + g_n)));
    return L::both(live, L::either(L::either(L::lt(f.d, L::set(g_n)), two_sided), f.facing));
  } else {
    live = L::both(live, L::either(two_sided, f.facing));
    return L::both(live, L::both(L::le(f.d, L::set(1.0f)), L::gt(f.d, L::set(0.0f))));
  }
}

// Step 4: the centre of the influence sphere in the receiver frame (world units), and the
// lanes whose sphere, grown by `reach` (r, or r + g for certain), holds the receiver.
template <class L>
[[nodiscard, gnu::always_inline]] inline typename L::M sphere_reaches(const FrameLanes<L>& frame, const LeafBlock& leaf,
                                                                      int l, float reach, typename L::F& ccx,
                                                                      typename L::F& ccy, typename L::F& ccz) {
  to_frame<L>(frame, leaf.cx() + l, leaf.cy() + l, leaf.cz() + l, leaf.width, ccx, ccy, ccz);
  const typename L::F grown = L::add(load_row<L>(leaf.radius() + l, leaf.width), L::set(reach));
  return L::le(dot3<L>(ccx, ccy, ccz, ccx, ccy, ccz), L::mul(grown, grown));
}

// Step 6: the face plane and the edge planes m_e = cross(p_e, p_e+1), oriented by the sign of
// the plane distance, into `out`, and |m_e| into `length`. Returns the lanes of `live` whose
// three edge planes are defined (1e-30 < |m_e|^2 <= max).
template <class L>
[[nodiscard, gnu::always_inline]] inline typename L::M store_planes(const CornerLanes<L>& t, const FaceLanes<L>& f,
                                                                    typename L::M live, int l, LeafSetup& out,
                                                                    typename L::F (&length)[3]) {
  using F = typename L::F;
  const F big = L::set(std::numeric_limits<float>::max());
  const F sign = L::select(L::gt(f.sd, L::set(0.0f)), L::set(1.0f), L::set(-1.0f));
  L::store(out.fx + l, L::mul(f.ux, sign)), L::store(out.fy + l, L::mul(f.uy, sign)), L::store(out.fz + l, L::mul(f.uz, sign));
  L::store(out.fd + l, f.d);
  const F* const corner[3][3] = {{&t.ax, &t.ay, &t.az}, {&t.bx, &t.by, &t.bz}, {&t.cx, &t.cy, &t.cz}};
  auto defined = live;
  for (int e = 0; e < 3; ++e) {
    const F px = *corner[e][0], py = *corner[e][1], pz = *corner[e][2];
    const F qx = *corner[(e + 1) % 3][0], qy = *corner[(e + 1) % 3][1], qz = *corner[(e + 1) % 3][2];
    const F mx = L::mul(L::sub(L::mul(py, qz), L::mul(qy, pz)), sign);
    const F my = L::mul(L::sub(L::mul(pz, qx), L::mul(qz, px)), sign);
    const F mz = L::mul(L::sub(L::mul(px, qy), L::mul(qx, py)), sign);
    const F length2 = dot3<L>(mx, my, mz, mx, my, mz);
    defined = L::both(defined, L::both(L::gt(length2, L::set(1e-30f)), L::le(length2, big)));
    length[e] = L::sqrt(length2);
    L::store(out.ex[e] + l, mx), L::store(out.ey[e] + l, my), L::store(out.ez[e] + l, mz);
    L::store(out.length[e] + l, length[e]);
  }
  return defined;
}

// Certain: a plane through (or numerically at) the origin, or an edge through it (`valid`
// false), decides nothing for sure, so its lanes are flat with no margins; elsewhere the edge
// planes' margins are g / d |m_e| and the edge cull widens by g / d.
template <class L>
[[gnu::always_inline]] inline void store_certain_margins(typename L::F d, typename L::M valid, typename L::F g,
                                                         const typename L::F (&length)[3], int l, LeafSetup& out) {
  using F = typename L::F;
  const auto flat = L::either(L::lt(d, g), L::not_(valid));
  const F g_over_d = L::div(g, d);
  for (int e = 0; e < 3; ++e) {
    L::store(out.margin[e] + l, L::select(flat, L::set(0.0f), L::mul(L::mul(g_over_d, length[e]), L::set(1.0f + 1e-5f))));
  }
  L::store(out.widen + l, L::mul(g_over_d, L::set(1.0f + 1e-5f)));
  out.flat |= static_cast<std::uint32_t>(L::bits(flat)) << l;
}

// The set-up of every triangle of `leaf` at the receiver of `frame`, as triangle_mask's numbered
// steps; returns the live lanes (bit l: triangle l may block a ray). g_world (certain only) is
// 2 delta in world units.
template <bool Certain>
[[nodiscard]] inline std::uint32_t leaf_setup(const KernelContext& ctx, const LeafBlock& leaf, const Frame& frame,
                                              float g_world, LeafSetup& out) {
  using L = Lanes8;
  using F = typename L::F;
  const FrameLanes<L> frame_lanes(frame);
  const F inv_r = L::set(ctx.inv_radius);
  const float g_n = g_world * ctx.inv_radius;
  const F g = L::set(g_n);
  std::uint32_t live = 0;
  out.use_cone = 0;
  out.flat = 0;
  for (int l = 0; l < leaf.width; l += L::kWidth) {
    CornerLanes<L> t;
    // 1. Into the receiver frame; the horizon (grown by g for certain).
    auto ok = corners_in_frame<L>(frame_lanes, leaf, l, Certain ? L::set(-g_world) : L::set(0.0f), inv_r, t);
    // 2-3. The face plane, its facing and distance.
    const auto two_sided = L::from_bits(leaf.two_sided >> l);
    const FaceLanes<L> face = face_plane<L>(t, ok);
    ok = face_kept<Certain, L>(face, two_sided, g_n, ok);
    // 4. The influence sphere.
    F ccx, ccy, ccz;
    ok = L::both(ok, sphere_reaches<L>(frame_lanes, leaf, l, Certain ? ctx.radius + g_world : ctx.radius, ccx, ccy, ccz));
    // 5. The triangle itself within r (pure only: it is only a cull, see CertainSetup).
    if constexpr (!Certain) {
      ok = L::both(ok, L::le(origin_triangle_distance2_lanes<L>(t.ax, t.ay, t.az, t.bx, t.by, t.bz, t.cx, t.cy, t.cz),
                             L::set(1.0f)));
    }
    // 6. The four planes; 6a. the cone of the clip sphere.
    F length[3];
    const auto valid = store_planes<L>(t, face, ok, l, out, length);
    L::store(out.ox + l, ccx), L::store(out.oy + l, ccy), L::store(out.oz + l, ccz);
    if constexpr (Certain) {
      store_certain_margins<L>(face.d, valid, g, length, l, out);
      ok = L::both(ok, certain_cone<L>(leaf, l, ccx, ccy, ccz, g_world, out));
    } else {
      ok = valid;
      pure_cone<L>(leaf, l, ccx, ccy, ccz, inv_r, out);
    }
    live |= static_cast<std::uint32_t>(L::bits(ok)) << l;
  }
  return live;
}
