#include "core/grazing.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/surface_rule.h"

namespace exao {
namespace {

using glm::dvec3;

double clamp01(double x) { return std::clamp(x, 0.0, 1.0); }

// Squared distance between segments [p1, q1] and [p2, q2] (Ericson, Real-Time Collision
// Detection 5.1.9).
double segment_segment_distance2(const dvec3& p1, const dvec3& q1, const dvec3& p2, const dvec3& q2) {
  const dvec3 d1 = q1 - p1, d2 = q2 - p2, r = p1 - p2;
  const double a = glm::dot(d1, d1), e = glm::dot(d2, d2), f = glm::dot(d2, r);
  double s = 0.0, t = 0.0;
  if (a <= 0.0 && e <= 0.0) return glm::dot(r, r);
  if (a <= 0.0) {
    t = clamp01(f / e);
  } else {
    const double c = glm::dot(d1, r);
    if (e <= 0.0) {
      s = clamp01(-c / a);
    } else {
      const double b = glm::dot(d1, d2), denom = a * e - b * b;
      s = denom > 0.0 ? clamp01((b * f - c * e) / denom) : 0.0;
      t = (b * s + f) / e;
      if (t < 0.0) {
        t = 0.0;
        s = clamp01(-c / a);
      } else if (t > 1.0) {
        t = 1.0;
        s = clamp01((b - c) / a);
      }
    }
  }
  const dvec3 gap = (p1 + d1 * s) - (p2 + d2 * t);
  return glm::dot(gap, gap);
}

// Squared distance from p to triangle (a, b, c) (Ericson 5.1.5).
double point_triangle_distance2(const dvec3& p, const dvec3& a, const dvec3& b, const dvec3& c) {
  const dvec3 ab = b - a, ac = c - a, ap = p - a;
  const auto dist2 = [&](const dvec3& q) { return glm::dot(p - q, p - q); };
  const double d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
  if (d1 <= 0.0 && d2 <= 0.0) return dist2(a);
  const dvec3 bp = p - b;
  const double d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
  if (d3 >= 0.0 && d4 <= d3) return dist2(b);
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return dist2(a + ab * (d1 / (d1 - d3)));
  const dvec3 cp = p - c;
  const double d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
  if (d6 >= 0.0 && d5 <= d6) return dist2(c);
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return dist2(a + ac * (d2 / (d2 - d6)));
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) return dist2(b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6))));
  const double denom = 1.0 / (va + vb + vc);
  if (!std::isfinite(denom)) return std::min({dist2(a), dist2(b), dist2(c)});
  return dist2(a + ab * (vb * denom) + ac * (vc * denom));
}

double largest_coordinate(const glm::vec3& v) {
  return std::max({std::abs(double(v.x)), std::abs(double(v.y)), std::abs(double(v.z))});
}

}  // namespace

GrazingTest::GrazingTest(const Scene& scene, const ShadowRays& rays) : scene_(&scene), rays_(rays) {
  const std::size_t n = scene.triangle_count();
  centre_.resize(n);
  reach_.resize(n);
  largest_.resize(n);
  for (std::size_t t = 0; t < n; ++t) {
    const auto tri = scene.triangle(t);
    const dvec3 a(tri[0]), b(tri[1]), c(tri[2]);
    centre_[t] = (a + b + c) / 3.0;
    const double radius =
        std::sqrt(std::max({glm::dot(a - centre_[t], a - centre_[t]), glm::dot(b - centre_[t], b - centre_[t]),
                            glm::dot(c - centre_[t], c - centre_[t])}));
    const double largest = std::max({largest_coordinate(tri[0]), largest_coordinate(tri[1]), largest_coordinate(tri[2])});
    largest_[t] = static_cast<float>(largest);
    // Out of reach: farther than r from every point of the triangle, with room for delta.
    reach_[t] = radius + double(rays.radius) + 1e-3 * (largest + double(rays.radius));
  }
}

double GrazingTest::closeness(const Frame& frame, int sample) const {
  return closeness(frame, std::span<const int>(&sample, 1)).front();
}

std::vector<double> GrazingTest::closeness(const Frame& frame, std::span<const int> samples) const {
  std::vector<double> out(samples.size(), std::numeric_limits<double>::infinity());
  const dvec3 o(frame.origin);
  const double origin_largest = largest_coordinate(frame.origin);
  // The segments exactly as Embree casts them: float world directions, float lengths.
  std::vector<dvec3> ends(samples.size());
  for (std::size_t k = 0; k < samples.size(); ++k) {
    const int i = samples[k];
    const glm::vec3 w = frame.to_world_direction(rays_.pattern.directions[static_cast<std::size_t>(i)]);
    ends[k] = o + dvec3(w) * double(rays_.pattern.lengths[static_cast<std::size_t>(i)] * rays_.radius);
  }
  for (std::size_t t = 0; t < centre_.size(); ++t) {
    const dvec3 gap = centre_[t] - o;
    if (glm::dot(gap, gap) > reach_[t] * reach_[t]) continue;
    const auto tri = scene_->triangle(t);
    // The surface rule: a triangle whose plane p' lies on blocks nothing anywhere; no ray grazes it.
    if (origin_on_plane(tri[0], tri[1], tri[2], frame.origin)) continue;
    const dvec3 a(tri[0]), b(tri[1]), c(tri[2]);
    const double ulp = 0x1p-24 * (std::max(origin_largest, double(largest_[t])) + double(rays_.radius));
    const dvec3 normal = glm::cross(b - a, c - a);
    const double normal_length = glm::length(normal);
    const double h = normal_length > 0.0 ? std::abs(glm::dot(normal, o - a)) / normal_length : 0.0;
    const double d_origin = std::sqrt(point_triangle_distance2(o, a, b, c));
    for (std::size_t k = 0; k < samples.size(); ++k) {
      const dvec3& e = ends[k];
      // (a) the segment near an edge.
      const double edge = std::sqrt(std::min({segment_segment_distance2(o, e, a, b), segment_segment_distance2(o, e, b, c),
                                              segment_segment_distance2(o, e, c, a)}));
      // (b) the end near the triangle.
      const double end = std::sqrt(point_triangle_distance2(e, a, b, c));
      // (c) the origin near the plane and the segment near the triangle: the segment's distance
      //     to the triangle is 0 where it crosses it, else the least of its ends' and the edges'.
      double segment = std::min({edge, end, d_origin});
      if (normal_length > 0.0) {
        const double so = glm::dot(normal, o - a), se = glm::dot(normal, e - a);
        if ((so <= 0.0) != (se <= 0.0) || so == 0.0 || se == 0.0) {
          const double s = so == se ? 0.0 : so / (so - se);
          const dvec3 x = o + (e - o) * s;
          segment = std::min(segment, std::sqrt(point_triangle_distance2(x, a, b, c)));
        }
      }
      const double start = std::max(h, segment);
      out[k] = std::min(out[k], std::min({edge, end, start}) / ulp);
    }
  }
  return out;
}

}  // namespace exao
