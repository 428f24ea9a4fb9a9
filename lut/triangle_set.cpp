#include "lut/triangle_set.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace exao::lut {

void bounding_sphere(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c, glm::vec3& centre, float& radius) {
  const glm::dvec3 pa(a), pb(b), pc(c);
  const glm::dvec3 ab = pb - pa, ac = pc - pa, bc = pc - pb;
  glm::dvec3 o;
  // Obtuse or right at a vertex (or collinear): the sphere on the opposite, longest edge.
  if (glm::dot(ab, ac) <= 0.0) {
    o = 0.5 * (pb + pc);
  } else if (glm::dot(-ab, bc) <= 0.0) {
    o = 0.5 * (pa + pc);
  } else if (glm::dot(-ac, -bc) <= 0.0) {
    o = 0.5 * (pa + pb);
  } else {
    // Acute: the circumcentre, a + (|ac|^2 (n x ab) + |ab|^2 (ac x n)) / (2 |n|^2), n = ab x ac.
    const glm::dvec3 n = glm::cross(ab, ac);
    o = pa + (glm::dot(ac, ac) * glm::cross(n, ab) + glm::dot(ab, ab) * glm::cross(ac, n)) / (2.0 * glm::dot(n, n));
  }
  centre = glm::vec3(o);
  // The radius from the float centre actually stored, in double (float differences are exact in
  // double), then one float step up: every vertex is inside in exact arithmetic.
  const glm::dvec3 co(centre);
  const double r2 = std::max({glm::dot(pa - co, pa - co), glm::dot(pb - co, pb - co), glm::dot(pc - co, pc - co)});
  radius = std::nextafter(static_cast<float>(std::sqrt(r2)), std::numeric_limits<float>::infinity());
}

TriangleSet TriangleSet::build(const Scene& scene) {
  const std::size_t n = scene.triangle_count();
  TriangleSet set;
  set.v0.resize(n);
  set.v1.resize(n);
  set.v2.resize(n);
  set.two_sided = scene.two_sided;
  set.cutout.assign(n, 0);
  if (scene.cutouts && scene.cutouts->any()) {
    set.cutouts = scene.cutouts;
    for (std::size_t t = 0; t < n; ++t) set.cutout[t] = scene.cutouts->tests(t) ? 1 : 0;
  }
  set.object = scene.object;
  set.object.resize(n, 0);
  set.set_vertices(scene.vertices);
  return set;
}

void TriangleSet::set_vertices(std::span<const glm::vec3> vertices) {
  const std::size_t n = size();
  v0.resize(n);
  v1.resize(n);
  v2.resize(n);
  centre.resize(n);
  radius.resize(n);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 4096), [&](const tbb::blocked_range<std::size_t>& range) {
    for (std::size_t t = range.begin(); t != range.end(); ++t) {
      v0[t] = vertices[3 * t];
      v1[t] = vertices[3 * t + 1];
      v2[t] = vertices[3 * t + 2];
      bounding_sphere(v0[t], v1[t], v2[t], centre[t], radius[t]);
    }
  });
}

}  // namespace exao::lut
