#pragma once
// exao::raster::ScreenPolygon: a convex polygon given in clip space, clipped against the near
// plane and the guard band (homogeneous Sutherland-Hodgman), projected and snapped to the
// subpixel grid. The clipped vertices a shared edge produces are computed from the edge's two
// end points in one canonical order, so two polygons that share an edge in clip space share it
// bit for bit on screen, and the rasterizer's fill rule gives each pixel centre on it to exactly
// one of them (watertight).

#include <array>
#include <cstdint>
#include <span>

#include "raster/projection.h"

namespace exao::raster {

struct ScreenPolygon {
  /// An input of up to 13 vertices (a 12-gon clipped by one plane), plus one per clip plane.
  static constexpr int kMaxInput = 13;
  static constexpr int kMaxVertices = kMaxInput + kClipPlanes;

  int count = 0;  // vertices; 0 when nothing is left on screen
  std::array<ScreenVertex, kMaxVertices> vertex;
  // The pixels whose centres the polygon may cover, clamped to the image: x0..x1, y0..y1
  // inclusive; empty when x0 > x1 or y0 > y1.
  int x0 = 0, y0 = 0, x1 = -1, y1 = -1;

  [[nodiscard]] bool empty() const { return count < 3 || x0 > x1 || y0 > y1; }
};

/// The first pixel whose centre (k + 1/2) * kSubpixel is at or right of (below) `lo` subpixels,
/// and the last at or left of (above) `hi`.
[[nodiscard]] constexpr std::int64_t first_pixel_centre(std::int64_t lo) {
  const std::int64_t num = lo - kSubpixel / 2;
  return num >= 0 ? (num + kSubpixel - 1) / kSubpixel : -((-num) / kSubpixel);
}
[[nodiscard]] constexpr std::int64_t last_pixel_centre(std::int64_t hi) {
  const std::int64_t num = hi - kSubpixel / 2;
  return num >= 0 ? num / kSubpixel : -((-num + kSubpixel - 1) / kSubpixel);
}

/// Clips the convex polygon `clip` (clip space, 3 .. kMaxInput vertices, either winding) to the
/// near plane and the guard band, projects it and snaps it. Consecutive vertices that snap to
/// the same point are merged; fewer than three left, or zero area, gives an empty polygon.
[[nodiscard]] ScreenPolygon make_screen_polygon(const Projection& projection, std::span<const ClipVertex> clip);

}  // namespace exao::raster
