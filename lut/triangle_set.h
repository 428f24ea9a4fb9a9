#pragma once
// exao::lut::TriangleSet: the scene's triangles as the mask code reads them, with each
// triangle's bounding sphere computed once. Every backend reads the same stored floats, so the
// influence-sphere test and the region clip of triangle_mask are the same everywhere.

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "core/cutouts.h"
#include "core/receiver_frame.h"
#include "core/scene.h"

namespace exao::lut {

/// One triangle as the mask kernels read it, in one cache line: the same floats as its
/// TriangleSet entry, so masks computed from either are the same bits. The BVH stores its leaf
/// triangles this way, since a receiver in dense geometry visits hundreds of them.
/// 64 bytes, stored from a 64-byte aligned base (not alignas(64): see core/mask.h's kMaskAlign).
struct PackedTriangle {
  glm::vec3 v0{0.0f}, v1{0.0f}, v2{0.0f};  // world space; the front face is counter-clockwise
  glm::vec3 centre{0.0f};                  // bounding sphere (TriangleSet::centre, radius)
  float radius = 0.0f;
  std::uint32_t two_sided = 0;
  std::uint32_t cutout = 0;  // 1: alpha-tested (TriangleSet::cutout): its mask bits go through the decision
  std::uint32_t object = 0;  // TriangleSet::object: a receiver may exclude it
};
static_assert(sizeof(PackedTriangle) == 64);

struct TriangleSet {
  // Structure of arrays, one entry per triangle, in the scene's order (index t = scene index).
  std::vector<glm::vec3> v0, v1, v2;    // world space; the front face is counter-clockwise
  std::vector<std::uint8_t> two_sided;  // 1: blocks rays from both sides
  std::vector<std::uint32_t> object;    // Scene::object (0 when the scene has none)
  std::vector<glm::vec3> centre;        // bounding sphere: the smallest sphere holding v0, v1, v2
  std::vector<float> radius;            // ... its radius, rounded up so that every vertex is inside
                                        // in exact arithmetic on the stored floats
  std::vector<std::uint8_t> cutout;     // 1: alpha-tested (Scene::cutouts->tests(scene index))
  /// The scene's cut-outs when any triangle is alpha-tested, else nullptr: a mask bit of a
  /// triangle with `cutout` set stands only where cutouts->blocks says so (filter_cutout_rays).
  std::shared_ptr<const Cutouts> cutouts;

  [[nodiscard]] std::size_t size() const { return two_sided.size(); }
  [[nodiscard]] PackedTriangle packed(std::size_t t) const {
    return {v0[t], v1[t], v2[t], centre[t], radius[t], two_sided[t], cutout[t], object[t]};
  }
  /// Whether triangle t may block the rays of `frame` (not of the object it excludes).
  [[nodiscard]] bool blocks_for(std::size_t t, const Frame& frame) const { return object[t] != frame.excluded_object; }

  /// Copies the scene's triangles and computes their spheres (in double, then the radius is
  /// rounded up to cover the float centre). Multithreaded; a few ms per million triangles.
  [[nodiscard]] static TriangleSet build(const Scene& scene);
  /// Moves the triangles to new positions (3 per triangle, this set's order), sidedness and
  /// objects kept: the spheres as build computes them. For a refit after a deformation.
  void set_vertices(std::span<const glm::vec3> vertices);
};

/// The smallest sphere holding a triangle: the circumsphere for an acute triangle, else the
/// sphere on the longest edge. Radius as stored in TriangleSet (rounded up). Degenerate
/// (collinear) triangles get the sphere on their longest edge.
void bounding_sphere(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c, glm::vec3& centre, float& radius);

}  // namespace exao::lut
