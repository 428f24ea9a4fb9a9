#pragma once
// exao::lut::Plane: the plane of DESIGN.md section 4, in the receiver frame and normalised units
// (r = 1). A sample point s is on its positive side iff dot(m, s) >= d.

#include <glm/glm.hpp>

namespace exao::lut {

struct Plane {
  glm::vec3 m{0.0f, 0.0f, 1.0f};  // unit normal, pointing away from the origin (the receiver)
  float d = 0.0f;                 // distance from the origin, >= 0 (edge planes: 0)
};

/// The positive-side test, written once so every twin evaluates the same float expression:
/// (m.x*s.x + m.y*s.y) + m.z*s.z >= d, with no fused multiply-add (-ffp-contract=off).
[[nodiscard]] inline bool on_positive_side(const Plane& plane, const glm::vec3& s) {
  return plane.m.x * s.x + plane.m.y * s.y + plane.m.z * s.z >= plane.d;
}

}  // namespace exao::lut
