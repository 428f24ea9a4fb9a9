#pragma once
// exao::engine::receiver_problem: what makes a receiver unusable, written once for every
// boundary that takes caller's points (the public API, the Python module). Engine::run assumes
// receivers that pass it.

#include <cfloat>
#include <cmath>

#include <glm/glm.hpp>

#include "core/coordinate_limit.h"
#include "core/receiver_frame.h"

namespace exao::engine {

/// Why `r` cannot be queried ("position is not finite", ...), or nullptr. The frame normalises
/// the normal: its squared length must be a normal float for 1/sqrt to be finite and exact enough.
[[nodiscard]] inline const char* receiver_problem(const glm::vec3& position, const glm::vec3& normal) {
  const auto finite = [](const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); };
  if (!finite(position)) return "position is not finite";
  if (!within_coordinate_limit(position)) return "position is beyond +-1e17 (Embree cannot cast rays from there)";
  if (!finite(normal)) return "normal is not finite";
  const float len2 = normal.x * normal.x + normal.y * normal.y + normal.z * normal.z;
  if (!(len2 >= FLT_MIN && len2 <= FLT_MAX)) return "normal has zero length (or is too short or long to normalise)";
  return nullptr;
}

}  // namespace exao::engine
