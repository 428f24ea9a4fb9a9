#include "core/surface_rule.h"

#include <algorithm>
#include <cmath>

#include "core/orientation.h"

namespace exao {

bool origin_on_plane(const glm::vec3& v0, const glm::vec3& v1, const glm::vec3& v2, const glm::vec3& origin) {
  const glm::dvec3 a(v0), b(v1), c(v2), o(origin);
  const glm::dvec3 normal = glm::cross(b - a, c - a);
  const double det = glm::dot(normal, a - o);  // |normal| times the distance from the plane
  const auto largest = [](const glm::dvec3& v) { return std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)}); };
  const double scale = std::max({largest(a), largest(b), largest(c), largest(o)});
  const double tolerance = kOnPlaneUlps * 0x1p-24 * scale;
  if (std::abs(det) <= tolerance * std::sqrt(glm::dot(normal, normal))) return true;
  // Off by more than the tolerance in double; only a sliver's normal, rounded, could still hide
  // an exact zero: the exact predicate settles it (a no-op cost elsewhere, it exits at stage A).
  return orientation(v0, v1, v2, origin) == 0;
}

}  // namespace exao
