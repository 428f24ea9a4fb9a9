#pragma once
// exao::orientation: the exact sign of the orientation of four points, for float inputs
// (Shewchuk, "Adaptive Precision Floating-Point Arithmetic and Fast Robust Geometric
// Predicates", 1997). The one question of the surface rule (core/surface_rule.h) that rounding
// must not decide: does the ray origin lie in a triangle's plane, exactly?

#include <glm/glm.hpp>

namespace exao {

/// The sign (-1, 0 or +1) of det(a - d, b - d, c - d), exactly, for the float coordinates as
/// given: 0 iff d lies in the plane of a, b, c (or a, b, c are collinear); +1 iff d is on the
/// side cross(b - a, c - a) points away from. A double evaluation with Shewchuk's static error
/// bound decides all but (nearly) coplanar inputs, in a few tens of flops; the rest are summed
/// exactly (24 products of three floats, each exact as two doubles, added by expansion
/// arithmetic). Finite inputs only (a NaN or infinity gives an unspecified sign). Exact also
/// with flush-to-zero and denormals-are-zero on, as in Embree's threads and lut::FlushDenormals,
/// because no intermediate comes near the double denormals; a float denormal input is then read
/// as 0, by this function and by the float code around it alike.
[[nodiscard]] int orientation(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c, const glm::vec3& d);

}  // namespace exao
