#pragma once
// exao::lut::ConeTest: the conservative mask of a bounding sphere (DESIGN.md section 4, "bounds of
// regions"), the exact per-ray form of the paper's circular node mask (Sec. 5, Fig. 4).
//
// A ray i (unit direction w_i, length l_i r, from the origin) can meet a sphere (centre c,
// radius rho, origin outside) only if the angle between w_i and c is at most asin(rho / |c|) and
// l_i r >= |c| - rho. The test inflates both, with one `margin` m (radians):
//   rho'  = rho + m |c|                      (covers relative rounding of |c| and of rho)
//   beta  = min(pi, asin(rho' / |c|) + m)    (covers rounding of the directions and the axis)
//   bit i = angle(w_i, c) <= beta  and  l_i r >= |c| - rho'
// all ones if |c| <= rho' (origin inside), none if c.z < -rho' (below the horizon: every ray has
// w.z > 0). The angle is compared in whichever form is well conditioned at beta: sines below
// pi/4, the cosine between pi/4 and 3pi/4, sines again above; comparing cosines alone would lose
// angles below ~3e-4 rad to the float spacing near 1.
//
// Nesting (why the BVH may cull with it): if sphere T lies inside sphere S, every bit of the test
// of T with margin m_T is a bit of the test of S with margin m_S >= 2 m_T + (rounding), because
// rho'_T + |c_S - c_T| <= rho'_S (|c_T| <= 2 |c_S| outside S), the cones nest (beta_T +
// angle(c_T, c_S) <= beta_S) and the reach nests (|c_S| - rho'_S <= |c_T| - rho'_T). The rounding
// here is a few float ulps relative to |c| (to_local subtracts and rotates, both relative), far
// below the gap (m_S - 2 m_T) |c_S|; tests/triangle_mask_test.cpp checks it on random spheres.

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/glm.hpp>

#include "core/mask.h"
#include "lut/lanes.h"
#include "lut/sample_arrays.h"

namespace exao::lut {

struct ConeTest {
  enum class Kind { None, All, Narrow, Middle, Wide };
  Kind kind = Kind::None;
  glm::vec3 axis{0.0f, 0.0f, 1.0f};  // c / |c|
  float sin2 = 0.0f;        // Narrow: upper bound on |w x axis|^2; Wide: lower bound
  float cos_min = 0.0f;     // Middle: lower bound on dot(w, axis)
  float min_length = 0.0f;  // l_i >= min_length (normalised units); <= 0 means every length
};

/// The test of a sphere at `centre` (receiver frame, world units) of radius `radius` (world
/// units) for rays of length <= `ray_radius` (r), with `margin` as above. Conservative: a NaN
/// or infinite input gives Kind::All.
[[nodiscard]] inline ConeTest make_cone_test(const glm::vec3& centre, float radius, float ray_radius, float margin) {
  ConeTest test;
  const glm::dvec3 c(centre);
  const double len = std::sqrt(glm::dot(c, c));
  const double inflated = static_cast<double>(radius) + static_cast<double>(margin) * len;
  if (!(std::isfinite(len) && std::isfinite(inflated)) || len <= inflated) {
    test.kind = ConeTest::Kind::All;
    return test;
  }
  if (c.z < -inflated) return test;  // Kind::None
  constexpr double kPi = 3.14159265358979323846;
  const double beta = std::min(kPi, std::asin(inflated / len) + static_cast<double>(margin));
  const glm::dvec3 axis = c / len;
  test.axis = glm::vec3(axis);
  // Thresholds rounded outwards by one float step, so the rounding never tightens the test.
  constexpr float kInf = std::numeric_limits<float>::infinity();
  const auto down = [](double x) { return std::nextafter(static_cast<float>(x), -kInf); };
  const auto up = [](double x) { return std::nextafter(static_cast<float>(x), kInf); };
  test.min_length = down((len - inflated) / static_cast<double>(ray_radius));
  if (beta < 0.25 * kPi) {
    test.kind = ConeTest::Kind::Narrow;
    test.sin2 = up(std::sin(beta) * std::sin(beta));
  } else if (beta <= 0.75 * kPi) {
    test.kind = ConeTest::Kind::Middle;
    test.cos_min = down(std::cos(beta));
  } else {
    test.kind = ConeTest::Kind::Wide;
    test.sin2 = std::max(0.0f, down(std::sin(beta) * std::sin(beta)));
  }
  return test;
}

/// The mask of a ConeTest over the pattern's directions and lengths.
template <class L, int Bits>
[[nodiscard]] Mask<Bits> cone_mask(const SampleArrays& samples, const ConeTest& test) {
  using Kind = ConeTest::Kind;
  if (test.kind == Kind::None) return {};
  if (test.kind == Kind::All) return Mask<Bits>::ones(samples.count());
  const auto ax = L::set(test.axis.x), ay = L::set(test.axis.y), az = L::set(test.axis.z);
  const auto sin2 = L::set(test.sin2), cos_min = L::set(test.cos_min), min_length = L::set(test.min_length);
  const auto zero = L::set(0.0f);
  const float* wx = samples.wx();
  const float* wy = samples.wy();
  const float* wz = samples.wz();
  const float* length = samples.length();
  const Kind kind = test.kind;
  return gather_bits<L, Bits>([&](int i) {
    const auto x = L::load(wx + i), y = L::load(wy + i), z = L::load(wz + i);
    const auto dot = L::add(L::add(L::mul(x, ax), L::mul(y, ay)), L::mul(z, az));
    // The length test also clears the padding lanes (NaN), whatever the angle test says.
    const auto reach = L::ge(L::load(length + i), min_length);
    if (kind == Kind::Middle) return L::both(reach, L::ge(dot, cos_min));
    const auto cx = L::sub(L::mul(y, az), L::mul(z, ay));
    const auto cy = L::sub(L::mul(z, ax), L::mul(x, az));
    const auto cz = L::sub(L::mul(x, ay), L::mul(y, ax));
    const auto p2 = L::add(L::add(L::mul(cx, cx), L::mul(cy, cy)), L::mul(cz, cz));
    if (kind == Kind::Narrow) return L::both(reach, L::both(L::gt(dot, zero), L::le(p2, sin2)));
    return L::both(reach, L::either(L::ge(dot, zero), L::ge(p2, sin2)));
  });
}

}  // namespace exao::lut
