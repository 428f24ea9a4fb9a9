#pragma once
// exao::lut::TriangleSet: the scene's triangles as the mask code reads them, with each
// triangle's bounding sphere computed once. Every backend reads the same stored floats, so the
// influence-sphere test and the region clip of triangle_mask are the same everywhere.

#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "core/scene.h"

namespace exao::lut {

struct TriangleSet {
  // Structure of arrays, one entry per triangle, in the scene's order (index t = scene index).
  std::vector<glm::vec3> v0, v1, v2;    // world space; the front face is counter-clockwise
  std::vector<std::uint8_t> two_sided;  // 1: blocks rays from both sides
  std::vector<glm::vec3> centre;        // bounding sphere: the smallest sphere holding v0, v1, v2
  std::vector<float> radius;            // ... its radius, rounded up so that every vertex is inside
                                        // in exact arithmetic on the stored floats

  [[nodiscard]] std::size_t size() const { return two_sided.size(); }

  /// Copies the scene's triangles and computes their spheres (in double, then the radius is
  /// rounded up to cover the float centre). Multithreaded; a few ms per million triangles.
  [[nodiscard]] static TriangleSet build(const Scene& scene);
};

/// The smallest sphere holding a triangle: the circumsphere for an acute triangle, else the
/// sphere on the longest edge. Radius as stored in TriangleSet (rounded up). Degenerate
/// (collinear) triangles get the sphere on their longest edge.
void bounding_sphere(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c, glm::vec3& centre, float& radius);

}  // namespace exao::lut
