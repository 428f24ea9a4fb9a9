#pragma once
// exao::GrazingTest: which rays are "grazing", the only rays on which two exact backends may
// disagree (DESIGN.md section 8, test 3). A mask kernel and Embree decide the same predicates
// ("is the sample point beyond the plane", "inside the edge") in different float arithmetic (the
// receiver frame, normalised, versus world space with Embree's precomputed edges), so a ray whose
// answer a rounding of the coordinates could flip may come out either way. Such a ray is
// grazing; every other ray must agree bit for bit.
//
// The definition, for ray i of a receiver (segment S from p' to e = p' + l_i r R_p w_i, in
// double from the floats both backends read) and a triangle T within reach:
//   delta(T) = kGrazingUlps * 2^-24 * (max(|p'|_inf, |v0|_inf, |v1|_inf, |v2|_inf) + r)
// (kGrazingUlps float ulps of the largest coordinate either backend subtracts), and S grazes T
// iff p' is not on T's plane (core/surface_rule.h: such a triangle blocks nothing in every
// backend) and any of
//   (a) S passes within delta(T) of one of T's three edges (segment-to-segment distance);
//   (b) S's end e is within delta(T) of T (the ray ends on the triangle);
//   (c) p' is within delta(T) of T's plane and S within delta(T) of T (the ray starts on the
//       plane, up to rounding, and crosses the triangle at t ~ 0, or runs along it).
// A ray is grazing iff it grazes some triangle of the scene.

#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "core/receiver_frame.h"
#include "core/scene.h"
#include "core/shadow_rays.h"

namespace exao {

/// delta in float ulps of the largest coordinate. The frame transform and Embree's edge and
/// depth tests each carry a few ulps of the coordinates they subtract, more for slivers; among
/// the rays that differed on the real scenes the largest distance was 16 ulps (p' in front of a
/// long sliver, docs/surface-rule.md), most were below 1. Four times that, and above the surface
/// rule's tolerance (kOnPlaneUlps = 16), so that case (c) covers the band just outside it.
inline constexpr double kGrazingUlps = 64.0;

class GrazingTest {
 public:
  /// For the triangles of `scene` (copied in double, with bounding spheres) and `rays`.
  GrazingTest(const Scene& scene, const ShadowRays& rays);

  /// The smallest distance, over the scene's triangles, that makes ray `sample` of the receiver
  /// at `frame` graze (the minimum of (a), (b), (c) above), in units of delta(T) / kGrazingUlps
  /// (one float ulp of the largest coordinate): the ray grazes iff the result <= kGrazingUlps.
  /// Infinity when no triangle is near. O(triangles): meant for the few rays that differ.
  [[nodiscard]] double closeness(const Frame& frame, int sample) const;

  /// closeness(frame, sample) <= kGrazingUlps.
  [[nodiscard]] bool grazes(const Frame& frame, int sample) const { return closeness(frame, sample) <= kGrazingUlps; }

  /// closeness for several rays of one receiver, one scan of the triangles (`samples` ascending
  /// or not; results in the same order).
  [[nodiscard]] std::vector<double> closeness(const Frame& frame, std::span<const int> samples) const;

 private:
  const Scene* scene_ = nullptr;
  ShadowRays rays_;
  std::vector<glm::dvec3> centre_;  // per triangle: vertex mean, and the largest vertex distance
  std::vector<double> reach_;       // ... plus r: a triangle farther than this from p' is out of reach
  std::vector<float> largest_;      // ... largest |coordinate| of its vertices
};

}  // namespace exao
