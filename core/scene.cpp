#include "core/scene.h"

#include "core/coordinate_limit.h"

#include <algorithm>
#include <cmath>

namespace exao {

Bounds Scene::bounds() const {
  Bounds b;
  const std::size_t model = vertices.size() - std::min(vertices.size(), 3 * ground_triangles);
  for (std::size_t i = 0; i < model; ++i) b.extend(vertices[i]);
  return b;
}

bool Scene::add_triangle(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c,
                         bool is_two_sided, std::int32_t material_index) {
  ++report.triangles_read;
  // Beyond the limit is as unusable as infinite: Embree would abort on rays from there.
  if (!within_coordinate_limit(a) || !within_coordinate_limit(b) || !within_coordinate_limit(c)) {
    ++report.non_finite_skipped;
    return false;
  }
  // Double precision, so that only truly degenerate triangles (repeated or collinear
  // vertices) are dropped, not merely small ones.
  const glm::dvec3 n = glm::cross(glm::dvec3(b) - glm::dvec3(a), glm::dvec3(c) - glm::dvec3(a));
  if (n == glm::dvec3(0.0)) {
    ++report.zero_area_skipped;
    return false;
  }
  vertices.insert(vertices.end(), {a, b, c});
  two_sided.push_back(is_two_sided ? 1 : 0);
  material.push_back(material_index);
  return true;
}

void apply_sidedness(Scene& scene, Sidedness sidedness) {
  if (sidedness == Sidedness::Auto) return;
  std::fill(scene.two_sided.begin(), scene.two_sided.end(), sidedness == Sidedness::Two ? 1 : 0);
}

std::size_t two_sided_count(const Scene& scene) {
  return static_cast<std::size_t>(std::count(scene.two_sided.begin(), scene.two_sided.end(), 1));
}

}  // namespace exao
