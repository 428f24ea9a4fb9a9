#pragma once
// The surface rule (docs/surface-rule.md): what "the segment p' -> p' + l r w hits the triangle"
// means for a segment that starts on the triangle's plane. Every backend follows it: the masks
// in lut::MaskEngine::triangle_mask (step 6b), the Embree reference in its occlusion filter.
//
//   The segment is half-open, (p', p' + l r w]: it hits a triangle iff it crosses the triangle's
//   plane at some t in (0, l r] at a point of the closed triangle (Embree's t > tnear = 0).
//   A triangle whose plane p' lies on blocks no ray: the segment touches that plane only at
//   its start, or lies in it and meets a triangle without thickness edge-on. "On" means within
//   kOnPlaneUlps float ulps of the largest coordinate involved, exactly 0 included: closer than
//   that, float arithmetic cannot tell p' from the plane (the receiver frame's rounding, and
//   Embree's, are each a few ulps), so each backend would answer by its own rounding.
//
// The test is one function on the stored floats, evaluated in double (exactly for p' exactly on
// the plane), so every backend gets the same answer for the same triangle and origin.

#include <glm/glm.hpp>

namespace exao {

/// The tolerance of origin_on_plane, in float ulps (2^-24) of the largest |coordinate| of p'
/// and the three vertices: 16, four times the few ulps that either backend's depth test carries,
/// far below the default origin offset (1e-4 of the scene's diagonal, thousands of ulps).
inline constexpr double kOnPlaneUlps = 16.0;

/// True iff `origin` lies on the plane of triangle (v0, v1, v2): its distance from the plane is
/// at most kOnPlaneUlps * 2^-24 * max(|origin|_inf, |v0|_inf, |v1|_inf, |v2|_inf), computed in
/// double from the floats, or it is exactly 0 (core/orientation.h). A degenerate triangle
/// (collinear vertices) is "on" every origin and blocks nothing either way. Finite inputs.
[[nodiscard]] bool origin_on_plane(const glm::vec3& v0, const glm::vec3& v1, const glm::vec3& v2, const glm::vec3& origin);

}  // namespace exao
