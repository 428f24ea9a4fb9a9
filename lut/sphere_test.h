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


namespace exao::lut {

struct SphereTest {
  enum class Kind { None, All, Rays };
  Kind kind = Kind::None;
  glm::vec3 centre{0.0f};  // c / r
  float radius2 = 0.0f;    // (rho' / r)^2, rounded up
  // The cone from the origin that holds the grown ball (Kind::Rays): axis c / |c|, half-angle
  // asin(rho' / |c|), with the sine rounded up by 1e-5 relative and the cosine down. A cluster
  // of rays whose cone misses it by more than kClusterSlack holds no bit of the mask
  // (lut/kernels-inl.h, sphere_reach). cone_sin = 2: the ball fills so much of the view (half-angle
  // over ~87 degrees) that the rounding argument no longer holds: every cluster is tested.
  glm::vec3 axis{0.0f, 0.0f, 1.0f};
  float cone_cos = -1.0f;
  float cone_sin = 2.0f;
};

/// The test of a sphere at `centre` (receiver frame, world units) of radius `radius` (world
/// units) for rays of length <= `ray_radius` (r), with `margin` as above (>= 0). A NaN or
/// infinite input gives Kind::All (nothing can be bounded).
[[nodiscard]] inline SphereTest make_sphere_test(const glm::vec3& centre, float radius, float ray_radius,
                                                 float margin) {
  // Float, with every rounding covered: |c| and the grown radius carry a few ulps (~3e-7
  // relative), far below the factors that round them up here (1e-6), and every comparison that
  // could go either way at the rounding level goes the conservative way (All, or a bigger ball).
  SphereTest test;
  const float len = std::sqrt(glm::dot(centre, centre));
  const float grown = (radius + margin * len) * (1.0f + 1e-6f);
  if (!(std::isfinite(len) && std::isfinite(grown)) || len <= grown * (1.0f + 1e-6f)) {
    test.kind = SphereTest::Kind::All;
    return test;
  }
  if (centre.z < -grown) return test;  // Kind::None
  const float inv_r = 1.0f / ray_radius;
  test.kind = SphereTest::Kind::Rays;
  test.centre = centre * inv_r;
  const float grown_r = grown * inv_r;
  test.radius2 = grown_r * grown_r * (1.0f + 1e-6f);
  const float sine = grown / len * (1.0f + 1e-5f);
  if (sine < 0.999f) {
    test.axis = centre / len;
    test.cone_sin = sine;
    test.cone_cos = std::sqrt(1.0f - sine * sine) * (1.0f - 1e-6f);
  }
  return test;
}

}  // namespace exao::lut
