#pragma once
// Conservative rasterisation of a triangle in texture space: every texel the triangle touches,
// even partly, so that no texel a bilinear lookup can reach along a chart's border is left
// empty. Coordinates are in texels: texel (x, y) covers [x, x+1] x [y, y+1], y = 0 the top row
// (glTF's v = 0 is the top of the image, so texel coordinates are just uv * size).

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include <glm/glm.hpp>

namespace exao::bake {

using UvTriangleCorners = std::array<glm::dvec2, 3>;

/// Twice the signed area, cross(b - a, c - a): its sign tells the winding (mirrored UV charts
/// have the other sign; both are fine).
[[nodiscard]] inline double signed_area2(const UvTriangleCorners& t) {
  const glm::dvec2 e1 = t[1] - t[0], e2 = t[2] - t[0];
  return e1.x * e2.y - e1.y * e2.x;
}

/// Calls visit(x, y) for each texel of the width x height grid whose square overlaps the
/// triangle's interior: the boxes overlap and no edge's line separates them (the separating-axis
/// test, exact for a triangle against a square). Touching along a line or at a point does not
/// count. A triangle of zero area visits nothing.
template <class Visit>
void rasterize_conservative(const UvTriangleCorners& tri, int width, int height, Visit&& visit) {
  const double area = signed_area2(tri);
  if (!(std::abs(area) > 0.0)) return;
  const glm::dvec2 lo = glm::min(tri[0], glm::min(tri[1], tri[2]));
  const glm::dvec2 hi = glm::max(tri[0], glm::max(tri[1], tri[2]));
  if (!(std::isfinite(lo.x) && std::isfinite(lo.y) && std::isfinite(hi.x) && std::isfinite(hi.y))) return;
  // Texels whose open square meets the open box: x < hi.x and x + 1 > lo.x.
  const int x0 = std::max(0, static_cast<int>(std::floor(lo.x)));
  const int y0 = std::max(0, static_cast<int>(std::floor(lo.y)));
  const int x1 = std::min(width - 1, static_cast<int>(std::ceil(hi.x)) - 1);
  const int y1 = std::min(height - 1, static_cast<int>(std::ceil(hi.y)) - 1);
  // Edge functions oriented so the interior is positive: e(p) = s * cross(b - a, p - a).
  const double s = area > 0.0 ? 1.0 : -1.0;
  std::array<glm::dvec2, 3> normal;  // gradient of each edge function
  std::array<double, 3> offset;
  for (int k = 0; k < 3; ++k) {
    const glm::dvec2 a = tri[static_cast<std::size_t>(k)], b = tri[static_cast<std::size_t>((k + 1) % 3)];
    normal[static_cast<std::size_t>(k)] = s * glm::dvec2(-(b.y - a.y), b.x - a.x);
    offset[static_cast<std::size_t>(k)] = -glm::dot(normal[static_cast<std::size_t>(k)], a);
  }
  for (int y = y0; y <= y1; ++y) {
    for (int x = x0; x <= x1; ++x) {
      bool separated = false;
      for (std::size_t k = 0; k < 3 && !separated; ++k) {
        // The square's corner furthest along the edge's inward normal.
        const glm::dvec2 corner(x + (normal[k].x > 0.0 ? 1.0 : 0.0), y + (normal[k].y > 0.0 ? 1.0 : 0.0));
        separated = glm::dot(normal[k], corner) + offset[k] <= 0.0;
      }
      if (!separated) visit(x, y);
    }
  }
}

/// Barycentric coordinates of p in the triangle (they sum to 1; all >= 0 inside). The triangle
/// must have non-zero area.
[[nodiscard]] inline glm::dvec3 barycentric(const UvTriangleCorners& t, const glm::dvec2& p) {
  const double area = signed_area2(t);
  const auto cross = [](const glm::dvec2& u, const glm::dvec2& v) { return u.x * v.y - u.y * v.x; };
  const double b0 = cross(t[1] - p, t[2] - p) / area;
  const double b1 = cross(t[2] - p, t[0] - p) / area;
  return {b0, b1, 1.0 - b0 - b1};
}

/// Barycentric coordinates of the point of the triangle closest to p, and that distance squared.
[[nodiscard]] inline glm::dvec3 closest_barycentric(const UvTriangleCorners& t, const glm::dvec2& p,
                                                    double& distance2) {
  const glm::dvec3 inside = barycentric(t, p);
  if (inside.x >= 0.0 && inside.y >= 0.0 && inside.z >= 0.0) {
    distance2 = 0.0;
    return inside;
  }
  glm::dvec3 best(1.0, 0.0, 0.0);
  distance2 = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 3; ++k) {
    const glm::dvec2 a = t[static_cast<std::size_t>(k)], b = t[static_cast<std::size_t>((k + 1) % 3)];
    const glm::dvec2 e = b - a;
    const double length2 = glm::dot(e, e);
    const double f = length2 > 0.0 ? std::clamp(glm::dot(p - a, e) / length2, 0.0, 1.0) : 0.0;
    const glm::dvec2 q = a + f * e;
    const double d2 = glm::dot(p - q, p - q);
    if (d2 < distance2) {
      distance2 = d2;
      best = glm::dvec3(0.0);
      best[k] = 1.0 - f;
      best[(k + 1) % 3] = f;
    }
  }
  return best;
}

}  // namespace exao::bake
