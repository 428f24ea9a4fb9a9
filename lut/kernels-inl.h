// The mask kernels of DESIGN.md section 4 for one instruction set: triangle masks, conservative
// sphere masks and plane masks, over the pattern's clusters. Included by lut/mask_kernels_isa.cpp
// and bvh/traverse_isa.cpp inside namespace EXAO_KERNEL_NS, after core/kernel_target.h (so it
// has no include guard and includes nothing); core/lanes-inl.h first. The contracts are those of
// lut/mask_engine.h.
//
// Clusters (lut/sample_arrays.h): every kernel takes a set of clusters `allowed` and computes
// only the bits of those clusters; the others are zero. Within them it further skips every
// cluster whose cone provably holds no bit of the answer, by one vector test over the cluster
// cones (kClusterSlack is the margin that makes "provably" hold under float rounding):
//  - sphere masks: a ray at angle phi from the centre direction c/|c| passes the centre at
//    distance |c| sin(phi) (or |c| when phi >= 90 degrees), so a cluster whose cone lies outside
//    the cone of half-angle asin(rho'/|c|) around c misses the grown ball. With that half-angle
//    below ~87 degrees (SphereTest::cone_sin < 0.999) and the cones apart by kClusterSlack in
//    cosine, sin^2(phi) - (rho'/|c|)^2 >= 4e-6, above the float error of |t w - c|^2 (~1e-6 |c|^2),
//    so the float test of sphere_mask clears every bit of the cluster too;
//  - triangle masks: the mask is clipped by the triangle's own sphere, so its cone culls as
//    above; and an edge plane with the cluster's cone entirely on its negative side, i.e.
//    dot(m, a) < -(sin(theta) + kClusterSlack) |m| for the axis a and half-angle theta, has
//    dot(m, s_i) < -kClusterSlack l_i |m| for every sample of the cluster, far beyond the float
//    error of the dot product (~4e-7 |m| |s|): the float plane test fails on each of them.
// Both are tested by tests/triangle_mask_test.cpp (ClusterCullingChangesNoBitAndATighterCullIsCaught),
// which also shows that a tighter cull than this (a negative slack) changes bits.

// The bits of the clusters in `clusters`, from a lane predicate: lanes(first) gives Lanes::M for
// samples [first, first + kWidth). Cluster k is bits [16 k, 16 k + 16).
template <int Bits, class Predicate>
[[nodiscard]] inline Mask<Bits> gather_clusters(std::uint64_t clusters, Predicate&& lanes) {
  Mask<Bits> mask;
  while (clusters) {
    const int k = std::countr_zero(clusters);
    clusters &= clusters - 1;
    std::uint64_t bits = 0;
    for (int j = 0; j < kSampleCluster; j += Lanes::kWidth) bits |= Lanes::bits(lanes(kSampleCluster * k + j)) << j;
    mask.words[k >> 2] |= bits << (16 * (k & 3));
  }
  return mask;
}

// The clusters whose cones a cone (unit axis, cos_s, sin_s) can reach.
template <int Bits>
[[nodiscard]] inline std::uint64_t sphere_reach(const SampleArrays& s, const glm::vec3& axis, float cos_s, float sin_s,
                                                float slack) {
  constexpr int kClusters = clusters_for_bits(Bits);
  const auto ax = Lanes::set(axis.x), ay = Lanes::set(axis.y), az = Lanes::set(axis.z);
  const auto cs = Lanes::set(cos_s), sn = Lanes::set(sin_s), margin = Lanes::set(slack);
  std::uint64_t reach = 0;
  for (int k = 0; k < kClusters; k += Lanes::kWidth) {
    const auto dot = Lanes::add(Lanes::add(Lanes::mul(ax, Lanes::load(s.cluster_x() + k)),
                                           Lanes::mul(ay, Lanes::load(s.cluster_y() + k))),
                                Lanes::mul(az, Lanes::load(s.cluster_z() + k)));
    // cos(theta_k + theta_s) - slack
    const auto bound = Lanes::sub(Lanes::sub(Lanes::mul(Lanes::load(s.cluster_cos() + k), cs),
                                             Lanes::mul(Lanes::load(s.cluster_sin() + k), sn)),
                                  margin);
    reach |= Lanes::bits(Lanes::ge(dot, bound)) << k;
  }
  return reach & kAllClusters<Bits>;
}

// The clusters on the non-negative side of all three edge planes (unnormalised normals m_e of
// lengths len_e), within reach of the cone (axis, cos_s, sin_s) when use_cone. Always inlined: out
// of line (as GCC chose once triangle_finish became a template) it cost 1.4% of a vertex bake.
template <int Bits>
[[nodiscard, gnu::always_inline]] inline std::uint64_t triangle_reach(const SampleArrays& s, const Plane (&edge)[3], const float (&len)[3],
                                                  bool use_cone, const glm::vec3& axis, float cos_s, float sin_s,
                                                  float slack) {
  constexpr int kClusters = clusters_for_bits(Bits);
  const auto margin = Lanes::set(slack);
  std::uint64_t reach = 0;
  for (int k = 0; k < kClusters; k += Lanes::kWidth) {
    const auto x = Lanes::load(s.cluster_x() + k), y = Lanes::load(s.cluster_y() + k), z = Lanes::load(s.cluster_z() + k);
    const auto widen = Lanes::add(Lanes::load(s.cluster_sin() + k), margin);
    auto ok = Lanes::ge(Lanes::set(1.0f), Lanes::set(0.0f));
    for (int e = 0; e < 3; ++e) {
      const auto dot = Lanes::add(Lanes::add(Lanes::mul(Lanes::set(edge[e].m.x), x), Lanes::mul(Lanes::set(edge[e].m.y), y)),
                                  Lanes::mul(Lanes::set(edge[e].m.z), z));
      ok = Lanes::both(ok, Lanes::ge(dot, Lanes::mul(widen, Lanes::set(-len[e]))));
    }
    if (use_cone) {
      const auto dot = Lanes::add(Lanes::add(Lanes::mul(Lanes::set(axis.x), x), Lanes::mul(Lanes::set(axis.y), y)),
                                  Lanes::mul(Lanes::set(axis.z), z));
      const auto bound = Lanes::sub(Lanes::sub(Lanes::mul(Lanes::load(s.cluster_cos() + k), Lanes::set(cos_s)),
                                               Lanes::mul(Lanes::load(s.cluster_sin() + k), Lanes::set(sin_s))),
                                    margin);
      ok = Lanes::both(ok, Lanes::ge(dot, bound));
    }
    reach |= Lanes::bits(ok) << k;
  }
  return reach & kAllClusters<Bits>;
}

// Bit i set iff point i (x[i], y[i], z[i]) is on the positive side of `plane` (all clusters):
// the mask a plane-table cell stores, and the exact test of one plane.
template <int Bits>
[[nodiscard]] inline Mask<Bits> plane_mask(const float* x, const float* y, const float* z, const Plane& plane) {
  const auto mx = Lanes::set(plane.m.x), my = Lanes::set(plane.m.y), mz = Lanes::set(plane.m.z), d = Lanes::set(plane.d);
  return gather_clusters<Bits>(kAllClusters<Bits>, [&](int i) {
    const auto dot = Lanes::add(Lanes::add(Lanes::mul(mx, Lanes::load(x + i)), Lanes::mul(my, Lanes::load(y + i))),
                                Lanes::mul(mz, Lanes::load(z + i)));
    return Lanes::ge(dot, d);
  });
}

// Bit i set iff sample point i is on the positive side of all three edge planes (d = 0) and of
// the triangle's plane, for the samples of `clusters`.
template <int Bits>
[[nodiscard]] inline Mask<Bits> triangle_planes_mask(const SampleArrays& samples, const Plane (&edge)[3],
                                                     const Plane& face, std::uint64_t clusters) {
  const auto e0x = Lanes::set(edge[0].m.x), e0y = Lanes::set(edge[0].m.y), e0z = Lanes::set(edge[0].m.z);
  const auto e1x = Lanes::set(edge[1].m.x), e1y = Lanes::set(edge[1].m.y), e1z = Lanes::set(edge[1].m.z);
  const auto e2x = Lanes::set(edge[2].m.x), e2y = Lanes::set(edge[2].m.y), e2z = Lanes::set(edge[2].m.z);
  const auto fx = Lanes::set(face.m.x), fy = Lanes::set(face.m.y), fz = Lanes::set(face.m.z), fd = Lanes::set(face.d);
  const auto zero = Lanes::set(0.0f);
  const float* px = samples.px();
  const float* py = samples.py();
  const float* pz = samples.pz();
  return gather_clusters<Bits>(clusters, [&](int i) {
    const auto x = Lanes::load(px + i), y = Lanes::load(py + i), z = Lanes::load(pz + i);
    const auto dot = [&](auto mx, auto my, auto mz) {
      return Lanes::add(Lanes::add(Lanes::mul(mx, x), Lanes::mul(my, y)), Lanes::mul(mz, z));
    };
    auto m = Lanes::ge(dot(fx, fy, fz), fd);
    m = Lanes::both(m, Lanes::ge(dot(e0x, e0y, e0z), zero));
    m = Lanes::both(m, Lanes::ge(dot(e1x, e1y, e1z), zero));
    return Lanes::both(m, Lanes::ge(dot(e2x, e2y, e2z), zero));
  });
}

// The mask of a SphereTest over the pattern's directions and lengths, for `clusters`.
template <int Bits>
[[nodiscard]] inline Mask<Bits> sphere_mask(const SampleArrays& samples, const SphereTest& test, std::uint64_t clusters) {
  if (test.kind == SphereTest::Kind::None) return {};
  if (test.kind == SphereTest::Kind::All) return Mask<Bits>::ones(samples.count()) & cluster_bits<Bits>(clusters);
  const auto cx = Lanes::set(test.centre.x), cy = Lanes::set(test.centre.y), cz = Lanes::set(test.centre.z);
  const auto radius2 = Lanes::set(test.radius2);
  const auto zero = Lanes::set(0.0f);
  const float* wx = samples.wx();
  const float* wy = samples.wy();
  const float* wz = samples.wz();
  const float* length = samples.length();
  return gather_clusters<Bits>(clusters, [&](int i) {
    const auto x = Lanes::load(wx + i), y = Lanes::load(wy + i), z = Lanes::load(wz + i);
    const auto along = Lanes::add(Lanes::add(Lanes::mul(x, cx), Lanes::mul(y, cy)), Lanes::mul(z, cz));
    // Padding lanes: the NaN length leaves t at 0 or NaN, and w = NaN makes q NaN: no bit.
    const auto t = Lanes::min(Lanes::max(along, zero), Lanes::load(length + i));
    const auto qx = Lanes::sub(Lanes::mul(t, x), cx), qy = Lanes::sub(Lanes::mul(t, y), cy),
               qz = Lanes::sub(Lanes::mul(t, z), cz);
    const auto q2 = Lanes::add(Lanes::add(Lanes::mul(qx, qx), Lanes::mul(qy, qy)), Lanes::mul(qz, qz));
    return Lanes::le(q2, radius2);
  });
}

// Near samples: when a cone is small, its few candidate samples come from the direction grid
// (lut/sample_arrays.h) and are tested one by one, with the same float expressions as the lanes.
// Every direction w with dot(w, axis) >= cos_bound has |w - axis| <= sqrt(2 - 2 cos_bound), so
// (w.x, w.y) lies in the square of that half-width around (axis.x, axis.y) (inflated for the
// rounding of this arithmetic); grid_cell is monotone, so the cells of the square's corners
// bound the cells of every such w. With cos_bound = cos(theta_s) - kClusterSlack, a sample
// outside is outside the cone by the slack, as a culled cluster is (the proof above).
struct NearCells {
  int x0 = 0, x1 = -1, y0 = 0, y1 = -1;
};
inline constexpr int kMaxNearCells = 16;  // a cap on the loop; the cost decides below it

[[nodiscard]] inline bool near_cells(const SampleArrays& s, const glm::vec3& axis, float sine, float cos_bound,
                                     NearCells& cells) {
  // The square is at least 2 sine wide: more than 4 cells then, whatever the rest says.
  if (sine * static_cast<float>(s.grid_size()) > 4.0f) return false;
  const float chord = std::sqrt(std::max(0.0f, 2.0f - 2.0f * cos_bound)) * (1.0f + 1e-5f) + 1e-6f;
  cells.x0 = s.grid_cell(axis.x - chord);
  cells.x1 = s.grid_cell(axis.x + chord);
  cells.y0 = s.grid_cell(axis.y - chord);
  cells.y1 = s.grid_cell(axis.y + chord);
  return (cells.x1 - cells.x0 + 1) * (cells.y1 - cells.y0 + 1) <= kMaxNearCells;
}

// The choice between the near samples, one by one, and the vectors of the clusters the cone
// reaches, by their cost in near-sample tests: the near path's set-up costs kNearSetupCost, a
// vector of Lanes::kWidth samples kVectorCost. The two give the same bits. Measured (issue 20,
// docs/speed.md): at N = 128 and 1024 the vectors win or tie at every width from sse2 up, so in
// practice the near path serves the scalar kernels and very small cones at sse2.
inline constexpr float kNearSetupCost = 4.0f;
inline constexpr float kVectorCost = 0.5f;
[[nodiscard]] inline float vector_cost(std::uint64_t reached) {
  return static_cast<float>(std::popcount(reached) * (kSampleCluster / Lanes::kWidth)) * kVectorCost;
}
// Whether any near path can be cheaper than the vectors of `reached` (before near_cells).
[[nodiscard]] inline bool near_may_pay(std::uint64_t reached) { return kNearSetupCost < vector_cost(reached); }
[[nodiscard]] inline bool near_is_cheaper(const SampleArrays& s, const NearCells& cells, std::uint64_t reached) {
  const int g = s.grid_size();
  const std::uint16_t* start = s.grid_start();
  int samples = 0;
  for (int y = cells.y0; y <= cells.y1; ++y) samples += start[y * g + cells.x1 + 1] - start[y * g + cells.x0];
  return kNearSetupCost + static_cast<float>(samples) < vector_cost(reached);
}

// Whether the cone (axis, sine, cos_bound) takes the near path for the clusters of `reached`:
// it is small enough for the grid (near_cells, which fills `cells`) and cheaper than the vectors.
[[nodiscard]] inline bool take_near_path(const SampleArrays& s, const glm::vec3& axis, float sine, float cos_bound,
                                         std::uint64_t reached, NearCells& cells) {
  return near_may_pay(reached) && near_cells(s, axis, sine, cos_bound, cells) && near_is_cheaper(s, cells, reached);
}

// Calls f(i) for every sample i of the cells whose cluster is in `allowed`.
template <class F>
inline void for_near_samples(const SampleArrays& s, const NearCells& cells, std::uint64_t allowed, F&& f) {
  const int g = s.grid_size();
  const std::uint16_t* start = s.grid_start();
  const std::uint16_t* samples = s.grid_samples();
  for (int y = cells.y0; y <= cells.y1; ++y) {
    for (int x = cells.x0; x <= cells.x1; ++x) {
      const int cell = y * g + x;
      for (int k = start[cell]; k < start[cell + 1]; ++k) {
        const int i = samples[k];
        if ((allowed >> (i / kSampleCluster)) & 1u) f(i);
      }
    }
  }
}

// One sample of sphere_mask, in the same float expression (min/max with x86's NaN rule).
[[nodiscard]] inline bool sphere_sample(const SampleArrays& s, const SphereTest& test, int i) {
  const float x = s.wx()[i], y = s.wy()[i], z = s.wz()[i];
  const float along = (x * test.centre.x + y * test.centre.y) + z * test.centre.z;
  const float clamped = along > 0.0f ? along : 0.0f;
  const float l = s.length()[i];
  const float t = clamped < l ? clamped : l;
  const float qx = t * x - test.centre.x, qy = t * y - test.centre.y, qz = t * z - test.centre.z;
  return (qx * qx + qy * qy) + qz * qz <= test.radius2;
}

// One sample of triangle_planes_mask, in the same float expressions.
[[nodiscard]] inline bool planes_sample(const SampleArrays& s, const Plane (&edge)[3], const Plane& face, int i) {
  const float x = s.px()[i], y = s.py()[i], z = s.pz()[i];
  const auto dot = [&](const glm::vec3& m) { return (m.x * x + m.y * y) + m.z * z; };
  return dot(face.m) >= face.d && dot(edge[0].m) >= 0.0f && dot(edge[1].m) >= 0.0f && dot(edge[2].m) >= 0.0f;
}

// The mask of a sphere test (make_sphere_test, or the BVH's children set up in lanes) for the
// clusters of `allowed`: the near samples when its cone is small, else the clusters its cone
// reaches.
template <int Bits>
[[nodiscard]] inline Mask<Bits> sphere_test_mask(const KernelContext& ctx, const SphereTest& test, std::uint64_t allowed,
                                                 KernelCounters* counters) {
  std::uint64_t clusters = allowed & kAllClusters<Bits>;
  if (test.kind == SphereTest::Kind::Rays && ctx.cull_clusters && test.cone_sin < 1.0f) {
    clusters &= sphere_reach<Bits>(*ctx.samples, test.axis, test.cone_cos, test.cone_sin, ctx.cluster_slack);
    NearCells cells;
    if (take_near_path(*ctx.samples, test.axis, test.cone_sin, test.cone_cos - ctx.cluster_slack, clusters, cells)) {
      Mask<Bits> mask;
      int tested = 0;
      for_near_samples(*ctx.samples, cells, clusters, [&](int i) {
        ++tested;
        if (sphere_sample(*ctx.samples, test, i)) mask.set(i);
      });
      if (counters) {
        ++counters->sphere_masks;
        counters->near_samples += static_cast<std::uint64_t>(tested);
      }
      return mask;
    }
  }
  if (counters) {
    ++counters->sphere_masks;
    if (test.kind == SphereTest::Kind::Rays) counters->cluster_tests += static_cast<std::uint64_t>(std::popcount(clusters));
  }
  return sphere_mask<Bits>(*ctx.samples, test, clusters);
}

// MaskEngine::region_mask restricted to `allowed` clusters.
template <int Bits>
[[nodiscard]] inline Mask<Bits> region_mask(const KernelContext& ctx, const glm::vec3& centre_local, float radius,
                                            float margin, std::uint64_t allowed, KernelCounters* counters) {
  return sphere_test_mask<Bits>(ctx, make_sphere_test(centre_local, radius, ctx.radius, margin), allowed, counters);
}

// What steps 1-6a of triangle_mask leave to the rest, for one triangle at one receiver: its
// planes in the receiver frame (normalised units) and the cone of its clip sphere. Computed one
// triangle at a time by triangle_setup below, or for a whole BVH leaf in lanes
// (bvh/leaf_setup-inl.h, in the same expressions, so the bits are the same).
struct TriangleSetup {
  Plane face;
  Plane edge[3];
  float edge_length[3];
  glm::vec3 centre;  // the bounding sphere's centre, receiver frame, world units
  glm::vec3 axis;    // the clip sphere's cone (step 6a), when use_cone
  float sine, cosine;
  bool use_cone;
};

// Steps 1-6a of triangle_mask: false when the triangle is culled (it blocks no ray).
[[nodiscard]] inline bool triangle_setup(const KernelContext& ctx, const PackedTriangle& tri, const Frame& frame,
                                         TriangleSetup& out) {
  // 1. Into the receiver frame. The horizon test comes first: it is the cheapest and culls most.
  glm::vec3 a = frame.to_local(tri.v0);
  glm::vec3 b = frame.to_local(tri.v1);
  glm::vec3 c = frame.to_local(tri.v2);
  if (a.z <= 0.0f && b.z <= 0.0f && c.z <= 0.0f) return false;
  const float inv_r = ctx.inv_radius;
  a *= inv_r;
  b *= inv_r;
  c *= inv_r;

  // 2. Facing: the origin must be strictly in front of a one-sided triangle's CCW face.
  const glm::vec3 n = glm::cross(b - a, c - a);
  if (!tri.two_sided && !(glm::dot(n, -a) > 0.0f)) return false;

  // 3. The triangle's plane: degenerate, too far (d > r), or through the origin.
  const float n_length = glm::length(n);
  if (!(n_length > 0.0f && std::isfinite(n_length))) return false;
  const glm::vec3 unit = n / n_length;
  const float signed_d = glm::dot(unit, a);
  const float d = std::abs(signed_d);
  if (!(d <= 1.0f) || d == 0.0f) return false;

  // 4. The influence sphere: the triangle's bounding sphere grown by r must hold the origin.
  const glm::vec3 centre = frame.to_local(tri.centre);
  const float reach = tri.radius + ctx.radius;
  if (glm::dot(centre, centre) > reach * reach) return false;

  // 5. The triangle itself within r.
  if (origin_triangle_distance2(a, b, c) > 1.0f) return false;

  // 6. The four planes (see lut/mask_engine.h for the orientation by the sign of d).
  const float sign = signed_d > 0.0f ? 1.0f : -1.0f;
  out.face = Plane{unit * sign, d};
  out.edge[0] = {glm::cross(a, b) * sign, 0.0f};
  out.edge[1] = {glm::cross(b, c) * sign, 0.0f};
  out.edge[2] = {glm::cross(c, a) * sign, 0.0f};
  for (int e = 0; e < 3; ++e) {
    const float length2 = glm::dot(out.edge[e].m, out.edge[e].m);
    if (!(length2 > 1e-30f && length2 <= std::numeric_limits<float>::max())) return false;
    out.edge_length[e] = std::sqrt(length2);
  }
  out.centre = centre;

  // 6a. The cone of the clip sphere, in float with the sine rounded up and the cosine down.
  const glm::vec3 cn = centre * inv_r;
  const float len = std::sqrt(glm::dot(cn, cn));
  const float grown = (tri.radius * inv_r + kTriangleMargin * len) * (1.0f + 1e-5f);
  const float sine = grown / len * (1.0f + 1e-5f);
  out.use_cone = len > grown && sine < 0.999f;
  out.axis = out.use_cone ? cn / len : glm::vec3(0.0f);
  out.sine = sine;
  out.cosine = out.use_cone ? std::sqrt(1.0f - sine * sine) * (1.0f - 1e-6f) : -1.0f;
  return true;
}

// The bits of `mask` outside triangle tri's clip sphere (step 7), sample by sample.
template <int Bits>
[[nodiscard]] inline std::uint64_t clip_removes(const KernelContext& ctx, const PackedTriangle& tri,
                                                const TriangleSetup& s, const Mask<Bits>& mask) {
  const SphereTest clip = make_sphere_test(s.centre, tri.radius, ctx.radius, kTriangleMargin);
  if (clip.kind == SphereTest::Kind::All) return 0;
  std::uint64_t removed = 0;
  for (int w = 0; w < Mask<Bits>::kWords; ++w) {
    for (std::uint64_t bits = mask.words[w]; bits; bits &= bits - 1) {
      removed += !sphere_sample(*ctx.samples, clip, 64 * w + std::countr_zero(bits));
    }
  }
  return removed;
}

// The surface rule (core/surface_rule.h) on a triangle's stored world floats.
[[nodiscard]] inline bool on_triangle_plane(const PackedTriangle& tri, const glm::vec3& origin) {
  return origin_on_plane(tri.v0, tri.v1, tri.v2, origin);
}

// The triangle the finish steps read only once a mask survives (the surface rule, the clip):
// PackedTriangle itself, or whatever else has a packed_of found by argument-dependent lookup
// (a lane of a BVH leaf, bvh/traverse-inl.h, whose floats are gathered only then).
[[nodiscard]] inline const PackedTriangle& packed_of(const PackedTriangle& tri) { return tri; }

// Steps 6a-7 of triangle_mask, after triangle_setup (or the leaf's set-up in lanes) has let the
// triangle through.
template <int Bits, class Triangle>
[[nodiscard]] inline Mask<Bits> triangle_finish(const KernelContext& ctx, const Triangle& tri,
                                                const TriangleSetup& s, const Frame& frame, std::uint64_t allowed,
                                                KernelCounters* counters) {
  const Plane& face = s.face;
  const Plane(&edge)[3] = s.edge;
  std::uint64_t clusters = allowed & kAllClusters<Bits>;
  if (ctx.cull_clusters && clusters) {
    // 6a. The clusters the triangle can reach: its edge planes (exact masks only: a table's
    //     planes carry cells' errors) and the cone of its clip sphere (both modes).
    if (ctx.exact) {
      clusters &= triangle_reach<Bits>(*ctx.samples, edge, s.edge_length, s.use_cone, s.axis, s.cosine, s.sine,
                                       ctx.cluster_slack);
    } else if (s.use_cone) {
      clusters &= sphere_reach<Bits>(*ctx.samples, s.axis, s.cosine, s.sine, ctx.cluster_slack);
    }
    NearCells cells;
    if (ctx.exact && s.use_cone &&
        take_near_path(*ctx.samples, s.axis, s.sine, s.cosine - ctx.cluster_slack, clusters, cells)) {
      // 6b for a small cone: the planes on the near samples only.
      Mask<Bits> mask;
      int tested = 0;
      for_near_samples(*ctx.samples, cells, clusters, [&](int i) {
        ++tested;
        if (planes_sample(*ctx.samples, edge, face, i)) mask.set(i);
      });
      if (counters) {
        ++counters->triangle_masks;
        counters->near_samples += static_cast<std::uint64_t>(tested);
      }
      if (mask.none()) return mask;
      if (on_triangle_plane(packed_of(tri), frame.origin)) return {};  // 6b
      if (counters) counters->clip_removed += clip_removes(ctx, packed_of(tri), s, mask);  // 7: see below
      return mask;
    }
  }
  if (counters) {
    ++counters->triangle_masks;
    counters->cluster_tests += static_cast<std::uint64_t>(std::popcount(clusters));
  }
  if (!clusters) return {};
  Mask<Bits> mask;
  if (ctx.exact) {
    mask = triangle_planes_mask<Bits>(*ctx.samples, edge, face, clusters);
  } else {
    mask = ctx.table->template lookup<Bits>(face.m, face.d);
    mask &= ctx.table->template lookup<Bits>(edge[0].m, 0.0f);
    mask &= ctx.table->template lookup<Bits>(edge[1].m, 0.0f);
    mask &= ctx.table->template lookup<Bits>(edge[2].m, 0.0f);
    mask &= cluster_bits<Bits>(clusters);
  }
  if (mask.none()) return mask;

  // 6b. The surface rule (core/surface_rule.h, docs/surface-rule.md): a triangle whose plane p'
  //     lies on blocks nothing. Decided on the stored world floats, not on d above (the frame's
  //     rounding moves d off 0), so Embree's filter reaches the same answer; only triangles that
  //     set a bit get here, and its place in the steps does not change the bits.
  if (on_triangle_plane(packed_of(tri), frame.origin)) return {};

  // 7. The clip by the triangle's own sphere, for a table's masks only: their planes carry the
  //    cells' errors. An exact mask's bit is a segment that crosses the triangle, which lies in
  //    its sphere (grown by 1e-5 |c|, far more than the float error), so there the clip removes
  //    nothing; with counters it is still computed, to show that (docs/speed.md).
  if (ctx.exact) {
    if (counters) counters->clip_removed += clip_removes(ctx, packed_of(tri), s, mask);
    return mask;
  }
  const SphereTest clip = make_sphere_test(s.centre, packed_of(tri).radius, ctx.radius, kTriangleMargin);
  if (clip.kind == SphereTest::Kind::All) return mask;
  if (counters) {
    ++counters->sphere_masks;
    counters->cluster_tests += static_cast<std::uint64_t>(std::popcount(occupied_clusters(mask)));
  }
  return mask & sphere_mask<Bits>(*ctx.samples, clip, occupied_clusters(mask));
}

// MaskEngine::triangle_mask restricted to `allowed` clusters (its steps 1-7), of one triangle.
template <int Bits>
[[nodiscard]] inline Mask<Bits> triangle_mask(const KernelContext& ctx, const PackedTriangle& tri, const Frame& frame,
                                              std::uint64_t allowed, KernelCounters* counters) {
  TriangleSetup setup;
  if (!triangle_setup(ctx, tri, frame, setup)) return {};
  return triangle_finish<Bits>(ctx, tri, setup, frame, allowed, counters);
}

// The same for triangle t of a TriangleSet.
template <int Bits>
[[nodiscard]] inline Mask<Bits> triangle_mask(const KernelContext& ctx, const TriangleSet& triangles, std::uint32_t t,
                                              const Frame& frame, std::uint64_t allowed, KernelCounters* counters) {
  return triangle_mask<Bits>(ctx, triangles.packed(t), frame, allowed, counters);
}

// ---------------------------------------------------------------------------------------------
// Certain masks (the `auto` method): for one triangle, the rays it blocks *for sure* and the rays
// it *may* block, with respect to Embree's own answer, so that every ray outside the difference
// is decided by the masks and the rest is cast with Embree (bvh/traverse-inl.h). The margin is
// the grazing classifier's (core/grazing.h): a ray that passes farther than delta from every
// edge of the triangle, does not end within delta of it, and starts farther than delta from its
// plane is not grazing, and there Embree and the exact masks agree. In normalised units (r = 1),
// with g = 2 delta and d >= g the plane distance:
//  - sure:  dot(unit, s) >= d + g, and dot(m_e, s) >= (g / d) |m_e| for the three edges. The
//    segment then crosses the plane at x with |x| >= d, and every point of it is at least
//    dot(m^_e, w) d / 2 >= delta from each edge line (it is dot(m^_e, w) t from the edge plane,
//    which holds the origin, and (t_x - t) d / t_x from the triangle's plane), its end g beyond
//    the plane: it hits the triangle's interior and grazes nothing of it;
//  - maybe: dot(unit, s) >= d - g and dot(m_e, s) >= -(g / d) |m_e|; a ray outside fails one of
//    them by that margin and stays farther than delta from every point of the triangle (the
//    same two distances), so Embree misses it too. With d < g (the origin near the plane: case
//    (c) of the classifier) nothing is sure and every ray the grown sphere reaches may be.
// The culls of steps 1-5 are those of triangle_mask with r grown by g, and the cluster culls
// use the sphere grown by g and the edge planes widened by g / d, so they drop no maybe bit.
// No clip by the triangle's own sphere (step 7): sure bits cross the triangle itself, and the
// maybe bits need not be tight. The float rounding of every quantity here is a few ulps of the
// coordinates, 1/64 of delta or less.
template <int Bits>
struct CertainMasks {
  Mask<Bits> sure;
  Mask<Bits> maybe;
};

// Both masks of the planes test in one pass over the clusters.
template <int Bits>
[[nodiscard]] inline CertainMasks<Bits> certain_planes_masks(const SampleArrays& samples, const Plane (&edge)[3],
                                                             const float (&margin)[3], const Plane& face, float g,
                                                             std::uint64_t clusters) {
  const auto e0x = Lanes::set(edge[0].m.x), e0y = Lanes::set(edge[0].m.y), e0z = Lanes::set(edge[0].m.z);
  const auto e1x = Lanes::set(edge[1].m.x), e1y = Lanes::set(edge[1].m.y), e1z = Lanes::set(edge[1].m.z);
  const auto e2x = Lanes::set(edge[2].m.x), e2y = Lanes::set(edge[2].m.y), e2z = Lanes::set(edge[2].m.z);
  const auto fx = Lanes::set(face.m.x), fy = Lanes::set(face.m.y), fz = Lanes::set(face.m.z);
  const auto f_sure = Lanes::set(face.d + g), f_maybe = Lanes::set(face.d - g);
  const auto m0 = Lanes::set(margin[0]), m1 = Lanes::set(margin[1]), m2 = Lanes::set(margin[2]);
  const auto n0 = Lanes::set(-margin[0]), n1 = Lanes::set(-margin[1]), n2 = Lanes::set(-margin[2]);
  const float* px = samples.px();
  const float* py = samples.py();
  const float* pz = samples.pz();
  CertainMasks<Bits> out;
  while (clusters) {
    const int k = std::countr_zero(clusters);
    clusters &= clusters - 1;
    std::uint64_t sure = 0, maybe = 0;
    for (int j = 0; j < kSampleCluster; j += Lanes::kWidth) {
      const int i = kSampleCluster * k + j;
      const auto x = Lanes::load(px + i), y = Lanes::load(py + i), z = Lanes::load(pz + i);
      const auto dot = [&](auto mx, auto my, auto mz) {
        return Lanes::add(Lanes::add(Lanes::mul(mx, x), Lanes::mul(my, y)), Lanes::mul(mz, z));
      };
      const auto f = dot(fx, fy, fz), d0 = dot(e0x, e0y, e0z), d1 = dot(e1x, e1y, e1z), d2 = dot(e2x, e2y, e2z);
      auto s = Lanes::both(Lanes::ge(f, f_sure), Lanes::ge(d0, m0));
      s = Lanes::both(s, Lanes::both(Lanes::ge(d1, m1), Lanes::ge(d2, m2)));
      auto m = Lanes::both(Lanes::ge(f, f_maybe), Lanes::ge(d0, n0));
      m = Lanes::both(m, Lanes::both(Lanes::ge(d1, n1), Lanes::ge(d2, n2)));
      sure |= Lanes::bits(s) << j;
      maybe |= Lanes::bits(m) << j;
    }
    out.sure.words[k >> 2] |= sure << (16 * (k & 3));
    out.maybe.words[k >> 2] |= maybe << (16 * (k & 3));
  }
  return out;
}

// What the set-up of the certain kernels (bvh/leaf_setup-inl.h, for a whole leaf in lanes: steps
// 1-6a with r grown by g) leaves to certain_finish, in normalised units. (triangle_mask's step 5,
// the exact distance, is only a cull: a triangle farther than r reaches no sample point, so its
// planes' masks are empty anyway; the certain set-up leaves it out.)
struct CertainSetup {
  Plane face;             // oriented by the sign of the plane distance, d = |distance|
  Plane edge[3];          // the edge planes (d = 0)
  float edge_length[3];   // |m_e|
  float margin[3];        // (g / d) |m_e|, rounded up: the sure and maybe thresholds
  float widen;            // g / d, rounded up: the extra slack of the edge cull
  glm::vec3 axis;         // the cone of the bounding sphere grown by g, when use_cone
  float cone_cos, cone_sin;
  bool use_cone;
  bool flat;              // the origin (numerically) on the plane or on an edge line: nothing is sure
};

/// The sure and maybe masks of one triangle at the receiver of `frame`, for the clusters of
/// `allowed`; `g_world` is 2 delta in world units (bvh/traverse-inl.h computes it per receiver),
/// after the set-up has let it through.
template <int Bits, class Triangle>
[[nodiscard]] inline CertainMasks<Bits> certain_finish(const KernelContext& ctx, const Triangle& tri,
                                                       const CertainSetup& s, const Frame& frame, float g_world,
                                                       std::uint64_t allowed, KernelCounters* counters) {
  const float g = g_world * ctx.inv_radius;
  const Plane& face = s.face;
  const Plane(&edge)[3] = s.edge;
  const float(&margin)[3] = s.margin;
  CertainMasks<Bits> out;
  std::uint64_t clusters = allowed & kAllClusters<Bits>;
  if (ctx.cull_clusters && clusters) {
    if (s.flat) {
      if (s.use_cone) clusters &= sphere_reach<Bits>(*ctx.samples, s.axis, s.cone_cos, s.cone_sin, ctx.cluster_slack);
    } else {
      // The edge cull of triangle_reach proves dot(m^_e, w) < -kClusterSlack for every ray of a
      // cluster; widened by g / d it proves dot(m^_e, w) < -(g / d), below the maybe threshold
      // for every sample point s = l w (l <= 1) as well.
      clusters &= triangle_reach<Bits>(*ctx.samples, edge, s.edge_length, s.use_cone, s.axis, s.cone_cos, s.cone_sin,
                                       ctx.cluster_slack + s.widen);
    }
    NearCells cells;
    if (!s.flat && s.use_cone &&
        take_near_path(*ctx.samples, s.axis, s.cone_sin, s.cone_cos - ctx.cluster_slack, clusters, cells)) {
      // A small cone: its few candidate samples one by one (the cells' proof above holds for the
      //  grown sphere's cone), with the same expressions as the lanes.
      const SampleArrays& samples = *ctx.samples;
      int tested = 0;
      for_near_samples(samples, cells, clusters, [&](int i) {
        ++tested;
        const float x = samples.px()[i], y = samples.py()[i], z = samples.pz()[i];
        const auto dot = [&](const glm::vec3& m) { return (m.x * x + m.y * y) + m.z * z; };
        const float f = dot(face.m), d0 = dot(edge[0].m), d1 = dot(edge[1].m), d2 = dot(edge[2].m);
        if (f >= face.d + g && d0 >= margin[0] && d1 >= margin[1] && d2 >= margin[2]) out.sure.set(i);
        if (f >= face.d - g && d0 >= -margin[0] && d1 >= -margin[1] && d2 >= -margin[2]) out.maybe.set(i);
      });
      if (counters) {
        ++counters->triangle_masks;
        counters->near_samples += static_cast<std::uint64_t>(tested);
      }
      if (out.maybe.none()) return out;
      if (on_triangle_plane(packed_of(tri), frame.origin)) return {};
      return out;
    }
  }
  if (counters) {
    ++counters->triangle_masks;
    counters->cluster_tests += static_cast<std::uint64_t>(std::popcount(clusters));
  }
  if (!clusters) return {};
  if (s.flat) {
    out.maybe = cluster_bits<Bits>(clusters) & Mask<Bits>::ones(ctx.samples->count());
  } else {
    out = certain_planes_masks<Bits>(*ctx.samples, edge, margin, face, g, clusters);
  }
  if (out.maybe.none()) return out;
  // 6b. The surface rule, on the stored floats, as Embree's filter decides it.
  if (on_triangle_plane(packed_of(tri), frame.origin)) return {};
  return out;
}
