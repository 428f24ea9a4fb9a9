#pragma once
// exao::raster::fragment_tests: the five culling tests the paper runs on every fragment that
// passes the inverted depth test (Sec. 4.2), in its order. Each may only skip a receiver whose
// mask for the triangle is empty (DESIGN.md section 4, "one mask function"): every comparison
// carries slack for the float rounding of both sides (raster/influence_volume.h), so a culled
// pair is one where triangle_mask's own tests (lut/mask_engine.h) return the empty mask.
//
//  1. Far depth: the triangle's nearest view depth exceeds the receiver's by more than r. (The
//     paper compares the *fragment's* depth; with a prism or a billboard that is the depth of the
//     volume's far side, which can lie well beyond r from a receiver the triangle does occlude,
//     e.g. a grazing view through a long prism. The triangle's own nearest depth makes the test
//     exact: |p' - q| >= depth(q) - depth(p') for every point q of the triangle.)
//  2. Bounding sphere: p' is farther than R + r from the triangle's bounding-sphere centre
//     (triangle_mask step 4).
//  3. Facing: a one-sided triangle with p' behind its plane (step 2).
//  4. Plane distance: p' farther than r from the triangle's plane (step 3).
//  5. Horizon: every vertex below the receiver's (tilted) tangent plane (step 1).

#include <cmath>

#include <glm/glm.hpp>

#include "core/receiver_frame.h"
#include "raster/influence_volume.h"

namespace exao::raster {

/// The number of tests passed before the first that culls: 0 .. 5 (5: compute the mask).
/// `depth` is the view depth of frame.origin.
[[nodiscard]] inline int fragment_tests(const TriangleCull& c, const Frame& frame, float depth) {
  if (c.near_depth - depth > c.depth_reach) return 0;
  const glm::vec3 from_centre = frame.origin - c.centre;
  if (glm::dot(from_centre, from_centre) > c.sphere_reach2) return 1;
  const float signed_distance = glm::dot(c.normal, frame.origin - c.v0);
  if (c.one_sided && signed_distance < -c.plane_slack) return 2;
  if (std::abs(signed_distance) > c.plane_reach) return 3;
  if (glm::dot(c.v0 - frame.origin, frame.normal) < -c.slack && glm::dot(c.v1 - frame.origin, frame.normal) < -c.slack &&
      glm::dot(c.v2 - frame.origin, frame.normal) < -c.slack) {
    return 4;
  }
  return 5;
}

/// The inverted depth test of a far face: the receiver (its ray origin, relative to the eye) is
/// on the inner side of the face's plane, i.e. the far surface along the pixel ray is at or
/// behind it.
[[nodiscard]] inline bool passes_depth_test(const DepthPlane& plane, const glm::vec3& from_eye, float slack) {
  return glm::dot(plane.m, from_eye) <= plane.h + slack;
}

}  // namespace exao::raster
