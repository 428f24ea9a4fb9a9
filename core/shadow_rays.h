#pragma once
// The shared shadow rays of DESIGN.md section 1: pattern, radius and origin offset, which turn a
// receiver into exactly N rays (p', R_p w_i, l_i r). Every backend takes its rays from here.

#include <algorithm>
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
  /// When > 0, the offset follows the point's own scale instead (the public API's default,
  /// include/exao/exao.hpp): eps(p) = max(origin_offset, offset_per_magnitude * max_k |p_k|),
  /// origin_offset then being the floor for points near the origin. 0: eps = origin_offset.
  float offset_per_magnitude = 0.0f;

  /// eps at `position` (world units): origin_offset, or the point-scaled offset above.
  [[nodiscard]] float offset_at(const glm::vec3& position) const {
    if (!(offset_per_magnitude > 0.0f)) return origin_offset;
    const float magnitude = std::max({std::abs(position.x), std::abs(position.y), std::abs(position.z)});
    return std::max(origin_offset, offset_per_magnitude * magnitude);
  }

  /// Half the pattern's smallest elevation: the normal's tilt never lets a ray below the horizon.
  [[nodiscard]] float max_tilt() const { return 0.5f * pattern.min_elevation; }
  [[nodiscard]] Frame frame(const Receiver& receiver) const {
    return make_frame(receiver, offset_at(receiver.position), max_tilt());
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

/// The public API's default offset (issue 22): 1e-4 of the point's largest coordinate
/// magnitude, at least 1e-6 world units. A far triangle moves the scene's box, and with it the
/// diagonal's offset, for every receiver; this one depends on the receiver alone. 1e-4 relative
/// is about 840 float ulps of that coordinate: far above the rounding of a surface point
/// computed from vertices of its own magnitude, and below what a contact shadow shows. The
/// floor is for points near the origin on triangles of larger coordinates (1e-6: about 8 ulps
/// of a vertex at 1).
inline constexpr float kPointOffsetFraction = 1e-4f;
inline constexpr float kPointOffsetFloor = 1e-6f;

}  // namespace exao
