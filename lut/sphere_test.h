#pragma once
// exao::lut::SphereTest: the conservative mask of a bounding sphere (DESIGN.md section 4, "bounds
// of regions"): the exact per-ray form of the paper's circular node mask (Sec. 5, Fig. 4), for
// equal and unequal ray lengths alike.
//
// Ray i is the segment from the origin to l_i w_i (normalised units, r = 1). It meets a ball
// (centre c, radius rho, origin outside) iff the point of the segment nearest to c,
// t_i w_i with t_i = clamp(dot(w_i, c), 0, l_i), lies in the ball. The test uses the ball grown by
// a `margin` m (radians: a relative distance):
//     rho' = rho + m |c|
//     bit i  <=>  |t_i w_i - c|^2 <= rho'^2
// all ones if |c| <= rho' (origin inside: any ray may hit), none if c.z < -rho' (below the
// horizon, where no ray goes: every w.z > 0).
//
// Conservative: a ray that meets the ball meets the grown ball; the float rounding of t_i w_i - c
// (a few ulps of |c| per component) and of c itself is far below m |c|.
// Nesting (why the BVH may cull with it): if ball T (margin m_T) lies inside ball S (margin
// m_S >= 2 m_T + rounding), then with |c_T| <= 2 |c_S| (c_T is within rho_S of c_S, and the
// origin is outside S, else S's mask is all ones) the grown T lies inside the grown S with a gap
// of (m_S - 2 m_T) |c_S|: a segment that meets the one meets the other, and the gap absorbs the
// rounding of both tests. tests/triangle_mask_test.cpp checks both properties on random spheres.
//
// This is tighter than a cone test plus a reach bound (angle(w, c) <= asin(rho/|c|) and
// l >= |c| - rho): a short ray aimed at the far side of a near sphere is not set.

#include <cmath>

#include <glm/glm.hpp>

#include "core/mask.h"
#include "lut/lanes.h"
#include "lut/sample_arrays.h"

namespace exao::lut {

struct SphereTest {
  enum class Kind { None, All, Rays };
  Kind kind = Kind::None;
  glm::vec3 centre{0.0f};  // c / r
  float radius2 = 0.0f;    // (rho' / r)^2, rounded up
};

/// The test of a sphere at `centre` (receiver frame, world units) of radius `radius` (world
/// units) for rays of length <= `ray_radius` (r), with `margin` as above (>= 0). A NaN or
/// infinite input gives Kind::All (nothing can be bounded).
[[nodiscard]] inline SphereTest make_sphere_test(const glm::vec3& centre, float radius, float ray_radius,
                                                 float margin) {
  SphereTest test;
  const glm::dvec3 c(centre);
  const double len = std::sqrt(glm::dot(c, c));
  const double grown = static_cast<double>(radius) + static_cast<double>(margin) * len;
  if (!(std::isfinite(len) && std::isfinite(grown)) || len <= grown) {
    test.kind = SphereTest::Kind::All;
    return test;
  }
  if (c.z < -grown) return test;  // Kind::None
  const double inv_r = 1.0 / static_cast<double>(ray_radius);
  test.kind = SphereTest::Kind::Rays;
  test.centre = glm::vec3(c * inv_r);
  // Rounded up: one float rounding is below 2^-24 relative, the factor adds 2^-22.
  test.radius2 = static_cast<float>(grown * grown * inv_r * inv_r) * (1.0f + 0x1p-22f);
  return test;
}

/// The mask of a SphereTest over the pattern's directions and lengths.
template <class L, int Bits>
[[nodiscard]] Mask<Bits> sphere_mask(const SampleArrays& samples, const SphereTest& test) {
  if (test.kind == SphereTest::Kind::None) return {};
  if (test.kind == SphereTest::Kind::All) return Mask<Bits>::ones(samples.count());
  const auto cx = L::set(test.centre.x), cy = L::set(test.centre.y), cz = L::set(test.centre.z);
  const auto radius2 = L::set(test.radius2);
  const auto zero = L::set(0.0f);
  const float* wx = samples.wx();
  const float* wy = samples.wy();
  const float* wz = samples.wz();
  const float* length = samples.length();
  return gather_bits<L, Bits>([&](int i) {
    const auto x = L::load(wx + i), y = L::load(wy + i), z = L::load(wz + i);
    const auto along = L::add(L::add(L::mul(x, cx), L::mul(y, cy)), L::mul(z, cz));
    // Padding lanes: the NaN length leaves t at 0 or NaN, and w = NaN makes q NaN: no bit.
    const auto t = L::min(L::max(along, zero), L::load(length + i));
    const auto qx = L::sub(L::mul(t, x), cx), qy = L::sub(L::mul(t, y), cy), qz = L::sub(L::mul(t, z), cz);
    const auto q2 = L::add(L::add(L::mul(qx, qx), L::mul(qy, qy)), L::mul(qz, qz));
    return L::le(q2, radius2);
  });
}

}  // namespace exao::lut
