#pragma once
// The largest coordinate exao accepts for a vertex, a receiver or a camera.

#include <cmath>

#include <glm/glm.hpp>

namespace exao {

/// Embree refuses (and Debian's build asserts on, aborting the program) any ray whose origin or
/// direction has a component beyond FLT_LARGE = 1.844e18 (embree/kernels/common/ray.h,
/// Ray::valid). A ray origin is a point plus an offset of at most the same size, so points are
/// kept ten times inside that: |x|, |y|, |z| <= 1e17. Float spacing there is ~1e10, so no real
/// scene comes near it.
inline constexpr float kMaxCoordinate = 1e17f;

/// Every component finite and within +-kMaxCoordinate (false for NaN).
[[nodiscard]] inline bool within_coordinate_limit(const glm::vec3& v) {
  return std::abs(v.x) <= kMaxCoordinate && std::abs(v.y) <= kMaxCoordinate && std::abs(v.z) <= kMaxCoordinate;
}

}  // namespace exao
