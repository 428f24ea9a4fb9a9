#pragma once
// Axis-aligned bounding box in world units.

#include <glm/glm.hpp>
#include <limits>

namespace exao {

struct Bounds {
  glm::vec3 lo{std::numeric_limits<float>::infinity()};
  glm::vec3 hi{-std::numeric_limits<float>::infinity()};

  void extend(const glm::vec3& p) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  [[nodiscard]] bool empty() const { return !(lo.x <= hi.x && lo.y <= hi.y && lo.z <= hi.z); }
  [[nodiscard]] glm::vec3 centre() const { return 0.5f * (lo + hi); }
  [[nodiscard]] glm::vec3 extent() const { return hi - lo; }
  /// Length of the box's diagonal; 0 for an empty box.
  [[nodiscard]] float diagonal() const { return empty() ? 0.0f : glm::length(hi - lo); }
};

}  // namespace exao
