#include "lut/mask_engine.h"

#include <cassert>
#include <cmath>
#include <limits>

#include "core/surface_rule.h"

namespace exao::lut {

const char* mask_mode_name(MaskMode mode) {
  switch (mode) {
    case MaskMode::Lut: return "lut";
    case MaskMode::Exact: return "exact";
  }
  return "?";
}

Result<MaskMode> parse_mask_mode(const std::string& name) {
  for (const MaskMode m : {MaskMode::Lut, MaskMode::Exact}) {
    if (name == mask_mode_name(m)) return m;
  }
  return fail("--masks: unknown mask mode '" + name + "' (lut or exact)");
}

Result<MaskEngine> MaskEngine::build(const ShadowRays& rays, MaskMode mode, int resolution) {
  if (auto ok = check_sample_count(rays.count()); !ok) return std::unexpected(ok.error());
  if (!(std::isfinite(rays.radius) && rays.radius > 0.0f)) return fail("--radius: must be a positive length");
  MaskEngine engine;
  engine.rays_ = rays;
  engine.mode_ = mode;
  engine.inv_radius_ = 1.0f / rays.radius;
  engine.samples_ = SampleArrays(rays.pattern);
  if (mode == MaskMode::Lut) {
    auto table = PlaneTable::build(rays.pattern, TableKind::Points, resolution);
    if (!table) return std::unexpected(table.error());
    engine.table_ = std::move(*table);
  }
  return engine;
}

Result<MaskEngine> MaskEngine::with_table(const ShadowRays& rays, PlaneTable table) {
  if (table.kind() != TableKind::Points || table.samples() != rays.count() ||
      table.pattern_hash() != lut::pattern_hash(rays.pattern)) {
    return fail("plane table: built for another sample pattern or kind than these rays");
  }
  auto engine = build(rays, MaskMode::Exact);
  if (!engine) return engine;
  engine->mode_ = MaskMode::Lut;
  engine->table_ = std::move(table);
  return engine;
}

float origin_triangle_distance2(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) {
  // Ericson's Voronoi-region walk with p = 0: ap = -a, bp = -b, cp = -c.
  const glm::vec3 ab = b - a, ac = c - a;
  const auto dist2 = [](const glm::vec3& q) { return glm::dot(q, q); };
  const float d1 = -glm::dot(ab, a), d2 = -glm::dot(ac, a);
  if (d1 <= 0.0f && d2 <= 0.0f) return dist2(a);
  const float d3 = -glm::dot(ab, b), d4 = -glm::dot(ac, b);
  if (d3 >= 0.0f && d4 <= d3) return dist2(b);
  const float vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0f && d1 >= 0.0f && d3 <= 0.0f) return dist2(a + (d1 / (d1 - d3)) * ab);
  const float d5 = -glm::dot(ab, c), d6 = -glm::dot(ac, c);
  if (d6 >= 0.0f && d5 <= d6) return dist2(c);
  const float vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0f && d2 >= 0.0f && d6 <= 0.0f) return dist2(a + (d2 / (d2 - d6)) * ac);
  const float va = d3 * d6 - d5 * d4;
  if (va <= 0.0f && (d4 - d3) >= 0.0f && (d5 - d6) >= 0.0f) {
    return dist2(b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b));
  }
  const float denom = 1.0f / (va + vb + vc);
  return dist2(a + ab * (vb * denom) + ac * (vc * denom));
}

template <int Bits, class L>
Mask<Bits> MaskEngine::triangle_mask(const TriangleSet& triangles, std::uint32_t t, const Frame& frame) const {
  assert(Bits == bits() && t < triangles.size());
  // 1. Into the receiver frame. The horizon test comes first: it is the cheapest and culls most.
  glm::vec3 a = frame.to_local(triangles.v0[t]);
  glm::vec3 b = frame.to_local(triangles.v1[t]);
  glm::vec3 c = frame.to_local(triangles.v2[t]);
  if (a.z <= 0.0f && b.z <= 0.0f && c.z <= 0.0f) return {};
  a *= inv_radius_;
  b *= inv_radius_;
  c *= inv_radius_;

  // 2. Facing: the origin must be strictly in front of a one-sided triangle's CCW face.
  const glm::vec3 n = glm::cross(b - a, c - a);
  if (!triangles.two_sided[t] && !(glm::dot(n, -a) > 0.0f)) return {};

  // 3. The triangle's plane: degenerate, too far (d > r), or through the origin.
  const float n_length = glm::length(n);
  if (!(n_length > 0.0f && std::isfinite(n_length))) return {};
  const glm::vec3 unit = n / n_length;
  const float signed_d = glm::dot(unit, a);
  const float d = std::abs(signed_d);
  if (!(d <= 1.0f) || d == 0.0f) return {};

  // 4. The influence sphere: the triangle's bounding sphere grown by r must hold the origin.
  const glm::vec3 centre = frame.to_local(triangles.centre[t]);
  const float reach = triangles.radius[t] + rays_.radius;
  if (glm::dot(centre, centre) > reach * reach) return {};

  // 5. The triangle itself within r.
  if (origin_triangle_distance2(a, b, c) > 1.0f) return {};

  // 6. The four planes. det(a, b, c) = dot(n, a) has the sign of signed_d; multiplying every
  //    edge normal by it puts the third vertex on the positive side, and the face normal by it
  //    points it away from the origin. The edge normals stay unnormalised: a plane through the
  //    origin tests the same points at any scale, and the table addresses d = 0 planes by
  //    direction only (m / max |m_k|); that saves three square roots and divisions. A
  //    (near-)zero edge normal (an edge through the origin, or a product under 1e-30, far from
  //    the denormals where the thread's FTZ mode could matter) blocks nothing.
  const float sign = signed_d > 0.0f ? 1.0f : -1.0f;
  const Plane face{unit * sign, d};
  Plane edge[3] = {{glm::cross(a, b) * sign, 0.0f}, {glm::cross(b, c) * sign, 0.0f}, {glm::cross(c, a) * sign, 0.0f}};
  for (const Plane& e : edge) {
    const float length2 = glm::dot(e.m, e.m);
    if (!(length2 > 1e-30f && length2 <= std::numeric_limits<float>::max())) return {};
  }
  Mask<Bits> mask;
  if (mode_ == MaskMode::Exact) {
    mask = triangle_planes_mask<L, Bits>(samples_, edge, face);
  } else {
    mask = table_->lookup<Bits>(face.m, face.d);
    mask &= table_->lookup<Bits>(edge[0].m, 0.0f);
    mask &= table_->lookup<Bits>(edge[1].m, 0.0f);
    mask &= table_->lookup<Bits>(edge[2].m, 0.0f);
  }
  if (mask.none()) return mask;

  // 6b. The surface rule (core/surface_rule.h, docs/surface-rule.md): a triangle whose plane
  //     p' lies on (exactly, or within kOnPlaneUlps of its coordinates) blocks nothing. One
  //     shared test on the stored world floats, not d above: the frame's rounding moves d off
  //     0 (a vertex at a room corner, p' in the floor's plane, would have half its rays blocked
  //     at t = 0), and Embree's filter must reach the same answer. Only triangles that set a bit
  //     get here, so the test costs nothing elsewhere; its place in the steps does not change
  //     the bits.
  if (origin_on_plane(triangles.v0[t], triangles.v1[t], triangles.v2[t], frame.origin)) return {};

  // 7. The clip by the triangle's own sphere (nothing to clip when the origin is inside it).
  const SphereTest clip = make_sphere_test(centre, triangles.radius[t], rays_.radius, kTriangleMargin);
  if (clip.kind == SphereTest::Kind::All) return mask;
  return mask & sphere_mask<L, Bits>(samples_, clip);
}

template <int Bits, class L>
Mask<Bits> MaskEngine::region_mask(const glm::vec3& centre_local, float radius, float margin) const {
  assert(Bits == bits());
  return sphere_mask<L, Bits>(samples_, make_sphere_test(centre_local, radius, rays_.radius, margin));
}

template <int Bits, class L>
Mask<Bits> MaskEngine::plane_mask(const Plane& plane) const {
  assert(Bits == bits());
  if (mode_ == MaskMode::Lut) return table_->lookup<Bits>(plane.m, plane.d);
  return lut::plane_mask<L, Bits>(samples_.px(), samples_.py(), samples_.pz(), plane);
}

// The one compiled copy of each, so every backend links the same arithmetic.
#define EXAO_INSTANTIATE(BITS, LANES)                                                                         \
  template Mask<BITS> MaskEngine::triangle_mask<BITS, LANES>(const TriangleSet&, std::uint32_t, const Frame&) \
      const;                                                                                                  \
  template Mask<BITS> MaskEngine::region_mask<BITS, LANES>(const glm::vec3&, float, float) const;            \
  template Mask<BITS> MaskEngine::plane_mask<BITS, LANES>(const Plane&) const;
#define EXAO_INSTANTIATE_ALL(LANES) \
  EXAO_INSTANTIATE(64, LANES)       \
  EXAO_INSTANTIATE(128, LANES)      \
  EXAO_INSTANTIATE(256, LANES)      \
  EXAO_INSTANTIATE(512, LANES)      \
  EXAO_INSTANTIATE(1024, LANES)

EXAO_INSTANTIATE_ALL(NativeLanes)
#if defined(EXAO_SIMD_AVX512) || defined(EXAO_SIMD_AVX2) || defined(EXAO_SIMD_SSE2)
EXAO_INSTANTIATE_ALL(ScalarLanes)
#endif

}  // namespace exao::lut
