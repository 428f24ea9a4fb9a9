#pragma once
// The surface rule (docs/surface-rule.md): what "the segment p' -> p' + l r w hits the triangle"
// means for a segment that starts on the triangle's plane. Every backend follows it: the masks
// in lut::MaskEngine::triangle_mask, the Embree reference in its occlusion filter.
//
//   The segment is half-open, (p', p' + l r w]: it hits a triangle iff it crosses the triangle's
//   plane at some t in (0, l r] at a point of the closed triangle. A triangle whose plane holds
//   p' exactly blocks no ray: the segment touches that plane only at its start (t = 0), or lies
//   in it and meets a triangle without thickness edge-on.
//
// "Exactly" is decided on the stored floats, in exact arithmetic (core/orientation.h), so that
// the answer does not depend on the frame's rounding (the masks) or on Embree's precomputed
// edges and normal (Embree gives about half the rays either way on a tilted plane).

#include <glm/glm.hpp>

#include "core/orientation.h"

namespace exao {

/// True iff `origin` lies exactly in the plane of triangle (v0, v1, v2) (or the triangle is
/// degenerate: its "plane" then holds the origin too, and it blocks nothing either way).
[[nodiscard]] inline bool origin_in_plane(const glm::vec3& v0, const glm::vec3& v1, const glm::vec3& v2,
                                          const glm::vec3& origin) {
  return orientation(v0, v1, v2, origin) == 0;
}

}  // namespace exao
