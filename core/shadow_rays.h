#pragma once
// The shared shadow rays of DESIGN.md section 1: pattern, radius and origin offset, which turn a
// receiver into exactly N rays (p', R_p w_i, l_i r). Every backend takes its rays from here.

#include <cmath>
#include <cstdio>
#include <string>

#include "core/coordinate_limit.h"
#include "core/error.h"
#include "core/receiver_frame.h"
#include "core/sample_pattern.h"

namespace exao {

struct ShadowRays {
  SamplePattern pattern;
  float radius = 1.0f;         // r: the longest ray, world units, > 0
  float origin_offset = 0.0f;  // eps: rays start at p + eps * n, world units, >= 0

  /// Half the pattern's smallest elevation: the normal's tilt never lets a ray below the horizon.
  [[nodiscard]] float max_tilt() const { return 0.5f * pattern.min_elevation; }
  [[nodiscard]] Frame frame(const Receiver& receiver) const {
    return make_frame(receiver, origin_offset, max_tilt());
  }
  [[nodiscard]] int count() const { return pattern.count; }
  /// Ray i's world direction at `frame`: the floats every ray caster casts and every cut-out
  /// decision (core/cutouts.h) rebuilds, so this is the one place they are computed.
  [[nodiscard]] glm::vec3 world_direction(const Frame& frame, int i) const {
    return frame.to_world_direction(pattern.directions[static_cast<std::size_t>(i)]);
  }
};

namespace detail {
// "1e+30" for an error message, rather than std::to_string's thirty-one digits.
[[nodiscard]] inline std::string short_number(float value) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", static_cast<double>(value));
  return text;
}
}  // namespace detail

/// Validates radius (finite, > 0) and offset (finite, >= 0), both at most kMaxCoordinate
/// (core/coordinate_limit.h: Embree refuses longer rays), and bundles them with the pattern.
[[nodiscard]] inline Result<ShadowRays> make_shadow_rays(SamplePattern pattern, float radius,
                                                         float origin_offset) {
  if (!(std::isfinite(radius) && radius > 0.0f)) {
    return fail("radius: must be a finite length > 0, got " + std::to_string(radius));
  }
  if (radius > kMaxCoordinate) return fail("radius: " + detail::short_number(radius) + " is beyond exao's limit of 1e17");
  if (!(std::isfinite(origin_offset) && origin_offset >= 0.0f)) {
    return fail("origin_offset: must be a finite length >= 0, got " + std::to_string(origin_offset));
  }
  if (origin_offset > kMaxCoordinate) {
    return fail("origin_offset: " + detail::short_number(origin_offset) + " is beyond exao's limit of 1e17");
  }
  return ShadowRays{std::move(pattern), radius, origin_offset};
}

/// The default origin offset: 1e-4 of the scene's bounding-box diagonal (DESIGN.md section 1).
inline constexpr float kDefaultOffsetFraction = 1e-4f;

}  // namespace exao
