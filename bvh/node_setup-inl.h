// The set-up of the (up to four) children of a BVH node at once, lane = child: the box culls of
// the traversal and make_sphere_test of each child's sphere (lut/sphere_test.h), in the same
// expressions, so each child's region mask is the same bits as region_mask's. Included by
// bvh/traverse_isa.cpp inside namespace EXAO_KERNEL_NS, after lut/kernels-inl.h.

struct alignas(16) ChildSetup {
  float cx[kMaxChildren], cy[kMaxChildren], cz[kMaxChildren];  // SphereTest::centre
  float radius2[kMaxChildren];
  float ax[kMaxChildren], ay[kMaxChildren], az[kMaxChildren];  // SphereTest::axis
  float cone_cos[kMaxChildren], cone_sin[kMaxChildren];
  std::uint32_t all = 0;  // bit k: child k's test is Kind::All (else Kind::Rays)

  [[nodiscard]] SphereTest test(int k) const {
    SphereTest t;
    if ((all >> k) & 1u) {
      t.kind = SphereTest::Kind::All;
      return t;
    }
    t.kind = SphereTest::Kind::Rays;
    t.centre = {cx[k], cy[k], cz[k]};
    t.radius2 = radius2[k];
    t.axis = {ax[k], ay[k], az[k]};
    t.cone_cos = cone_cos[k];
    t.cone_sin = cone_sin[k];
    return t;
  }
};

// The children of `node` that survive the box culls (farther than reach2, or below the tangent
// plane by more than slack) and whose sphere (radius grown by `grow`, margin kNodeMargin) is not
// below the horizon; their tests are in `out`. inv_r is 1 / ray_radius, as make_sphere_test
// computes it.
[[nodiscard]] inline std::uint32_t child_setup(const Node& node, const Frame& frame, float reach2, float slack,
                                               float grow, float ray_radius, ChildSetup& out) {
  using L = Lanes4;
  using F = typename L::F;
  const glm::vec3 o = frame.origin;
  const glm::vec3 n = frame.normal;
  const F ox = L::set(o.x), oy = L::set(o.y), oz = L::set(o.z);
  const F zero = L::set(0.0f), half_ = L::set(0.5f), big = L::set(std::numeric_limits<float>::max());
  const float inv_r = 1.0f / ray_radius;
  out.all = 0;
  std::uint32_t live = 0;
  for (int k = 0; k < kMaxChildren; k += L::kWidth) {
    const F lx = L::loadu(node.lo_x + k), ly = L::loadu(node.lo_y + k), lz = L::loadu(node.lo_z + k);
    const F hx = L::loadu(node.hi_x + k), hy = L::loadu(node.hi_y + k), hz = L::loadu(node.hi_z + k);
    // The box farther than r (std::max({lo - o, 0, o - hi}) per axis).
    const F dx = L::max(L::max(L::sub(lx, ox), zero), L::sub(ox, hx));
    const F dy = L::max(L::max(L::sub(ly, oy), zero), L::sub(oy, hy));
    const F dz = L::max(L::max(L::sub(lz, oz), zero), L::sub(oz, hz));
    auto ok = L::le(dot3<L>(dx, dy, dz, dx, dy, dz), L::set(reach2));
    // Highest point of the box above the tangent plane: centre height + half extents along |n|.
    const F mx = L::mul(half_, L::add(lx, hx)), my = L::mul(half_, L::add(ly, hy)), mz = L::mul(half_, L::add(lz, hz));
    const F ex = L::mul(half_, L::sub(hx, lx)), ey = L::mul(half_, L::sub(hy, ly)), ez = L::mul(half_, L::sub(hz, lz));
    const F top = L::add(dot3<L>(L::sub(mx, ox), L::sub(my, oy), L::sub(mz, oz), L::set(n.x), L::set(n.y), L::set(n.z)),
                         dot3<L>(ex, ey, ez, L::set(std::abs(n.x)), L::set(std::abs(n.y)), L::set(std::abs(n.z))));
    ok = L::both(ok, L::ge(top, L::set(-slack)));
    // The child's sphere in the receiver frame, and make_sphere_test's expressions.
    const F wx = L::sub(L::loadu(node.centre_x + k), ox), wy = L::sub(L::loadu(node.centre_y + k), oy),
            wz = L::sub(L::loadu(node.centre_z + k), oz);
    const F cx = dot3<L>(wx, wy, wz, L::set(frame.tangent.x), L::set(frame.tangent.y), L::set(frame.tangent.z));
    const F cy = dot3<L>(wx, wy, wz, L::set(frame.bitangent.x), L::set(frame.bitangent.y), L::set(frame.bitangent.z));
    const F cz = dot3<L>(wx, wy, wz, L::set(n.x), L::set(n.y), L::set(n.z));
    const F len = L::sqrt(dot3<L>(cx, cy, cz, cx, cy, cz));
    const F radius = L::add(L::loadu(node.radius + k), L::set(grow));
    const F grown = L::mul(L::add(radius, L::mul(L::set(lut::kNodeMargin), len)), L::set(1.0f + 1e-6f));
    const auto rays = L::both(L::both(L::le(len, big), L::le(grown, big)), L::gt(len, L::mul(grown, L::set(1.0f + 1e-6f))));
    ok = L::both(ok, L::not_(L::both(rays, L::lt(cz, L::neg(grown)))));
    const F r_inv = L::set(inv_r);
    L::store(out.cx + k, L::mul(cx, r_inv)), L::store(out.cy + k, L::mul(cy, r_inv)), L::store(out.cz + k, L::mul(cz, r_inv));
    const F grown_r = L::mul(grown, r_inv);
    L::store(out.radius2 + k, L::mul(L::mul(grown_r, grown_r), L::set(1.0f + 1e-6f)));
    const F sine = L::mul(L::div(grown, len), L::set(1.0f + 1e-5f));
    const auto cone = L::lt(sine, L::set(0.999f));
    L::store(out.ax + k, L::select(cone, L::div(cx, len), zero));
    L::store(out.ay + k, L::select(cone, L::div(cy, len), zero));
    L::store(out.az + k, L::select(cone, L::div(cz, len), L::set(1.0f)));
    L::store(out.cone_sin + k, L::select(cone, sine, L::set(2.0f)));
    L::store(out.cone_cos + k,
             L::select(cone, L::mul(L::sqrt(L::sub(L::set(1.0f), L::mul(sine, sine))), L::set(1.0f - 1e-6f)), L::set(-1.0f)));
    out.all |= static_cast<std::uint32_t>(L::bits(L::not_(rays))) << k;
    live |= static_cast<std::uint32_t>(L::bits(ok)) << k;
  }
  return live & ((1u << node.child_count) - 1u);
}
