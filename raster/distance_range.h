#pragma once
// exao::raster::range_mask: a triangle's mask restricted to a range of distances along the rays,
// for level of detail (paper Sec. 4.3). A triangle of a level with range [r_min, r_max] must
// block only the rays that meet it at a distance t from the origin with r_min < t <= r_max:
// nearer, the finer geometry of the level below decides; farther, the coarser one above. The
// paper: "we simply use r_max in place of r. To account for r_min, we need to perform an
// additional mask lookup, similar to the one in Figure 1d".
//
// The maths. In the receiver frame let the triangle's plane be dot(n, x) = d with d >= 0 (n not
// normalised, oriented away from the origin). Ray i, direction w_i, crosses it at
// t_i = d / dot(n, w_i) when dot(n, w_i) > 0. So
//     t_i <= a   <=>   dot(n, w_i) * a >= d,
// a plane test on the unit directions (Fig. 1d's test, with the plane moved to distance d / a),
// the same for every falloff: the triangle mask already holds t_i <= l_i r. Then
//     mask[r_min, r_max] = triangle_mask & nearer(r_max) & ~nearer(r_min),
// with nearer(r) = all rays and nearer(0) = none. The ranges [0, a] and [a, r] split the rays of
// [0, r] exactly in two (t <= a, t > a) whatever the rounding, because both evaluate the same
// nearer(a), bit for bit; that is what lets the levels tile the distance axis without gaps.
//
// Culling. nearer(a) is also empty when the triangle is farther than a from the origin (squared
// float distance > a^2): then no ray can meet it within a, and a backend that culls such a
// receiver with its own (slacker) distance tests, as the raster influence volumes built with
// r_max do, culls exactly what this function says is empty, in Lut mode too, where the triangle
// mask carries the table's stray bits (rays that miss the triangle by a cell but may cross its
// plane within a).
//
// Built from MaskEngine's public sample arrays (the directions w_i), so it does not depend on how
// the engine computes triangle masks.

#include <cstdint>
#include <limits>

#include <glm/glm.hpp>

#include "core/mask.h"
#include "core/receiver_frame.h"
#include "lut/mask_engine.h"
#include "lut/triangle_set.h"

namespace exao::raster {

/// A triangle's distance range along the rays, world units: it blocks a ray only where the ray
/// meets it at distance t with r_min < t <= r_max (t <= r_max for r_min = 0). r_min >= 0,
/// r_max > r_min; r_max >= r (the engine's radius) means no upper limit.
struct DistanceRange {
  float r_min = 0.0f;
  float r_max = std::numeric_limits<float>::infinity();
};

/// Rays whose crossing of the plane of the triangle (a, b, c) (receiver frame, world units) lies
/// at distance t <= `reach` (world units, > 0) from the origin; empty when the triangle is
/// farther than `reach` or degenerate. See the header comment.
template <int Bits>
[[nodiscard]] Mask<Bits> nearer_than(const lut::SampleArrays& samples, const glm::vec3& a, const glm::vec3& b,
                                     const glm::vec3& c, float reach) {
  Mask<Bits> out;
  if (!(lut::origin_triangle_distance2(a, b, c) <= reach * reach)) return out;
  glm::vec3 n = glm::cross(b - a, c - a);
  float d = glm::dot(n, a);
  if (d < 0.0f) {
    n = -n;
    d = -d;
  }
  if (!(glm::dot(n, n) > 0.0f)) return out;
  const float* wx = samples.wx();
  const float* wy = samples.wy();
  const float* wz = samples.wz();
  // Padding entries are NaN: their comparison fails, so bits >= N stay clear.
  for (int w = 0; w < Mask<Bits>::kWords; ++w) {
    std::uint64_t word = 0;
    for (int j = 0; j < 64; ++j) {
      const int i = 64 * w + j;
      const float dot = (n.x * wx[i] + n.y * wy[i]) + n.z * wz[i];
      word |= std::uint64_t{dot * reach >= d} << j;
    }
    out.words[static_cast<std::size_t>(w)] = word;
  }
  return out;
}

/// triangle_mask of triangle t at `frame` (restricted to `allowed` clusters, as triangle_mask
/// is), restricted to `range` (header comment). With range = [0, >= r] it is triangle_mask itself.
template <int Bits>
[[nodiscard]] Mask<Bits> range_mask(const lut::MaskEngine& engine, const lut::TriangleSet& triangles, std::uint32_t t,
                                     const Frame& frame, const DistanceRange& range,
                                     std::uint64_t allowed = lut::kAllClusters<Bits>) {
  Mask<Bits> mask = engine.triangle_mask<Bits>(triangles, t, frame, allowed);
  const bool capped = range.r_max < engine.rays().radius;
  if (mask.none() || (!capped && range.r_min <= 0.0f)) return mask;
  const glm::vec3 a = frame.to_local(triangles.v0[t]);
  const glm::vec3 b = frame.to_local(triangles.v1[t]);
  const glm::vec3 c = frame.to_local(triangles.v2[t]);
  if (capped) mask = mask & nearer_than<Bits>(engine.sample_arrays(), a, b, c, range.r_max);
  if (range.r_min > 0.0f) mask = and_not(mask, nearer_than<Bits>(engine.sample_arrays(), a, b, c, range.r_min));
  return mask;
}

}  // namespace exao::raster
