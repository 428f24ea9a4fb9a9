#include "raster/draw_triangle.h"

#include <algorithm>
#include <cmath>

#include "raster/screen_polygon.h"

namespace exao::raster {

DrawTriangle prepare_triangle(const Scene& scene, const Projection& projection, std::size_t t) {
  DrawTriangle d;
  for (int k = 0; k < 3; ++k) d.clip[static_cast<std::size_t>(k)] = projection.to_clip(scene.vertices[3 * t + static_cast<std::size_t>(k)]);
  if (d.clip[0].w < projection.near && d.clip[1].w < projection.near && d.clip[2].w < projection.near) return d;
  // Plane n . (x, y, w) = e through the clip vertices; on the ray (ndc_x w, ndc_y w, w):
  // 1/w = (n.x ndc_x + n.y ndc_y + n.z) / e.
  const glm::dvec3 p0(d.clip[0].x, d.clip[0].y, d.clip[0].w);
  const glm::dvec3 p1(d.clip[1].x, d.clip[1].y, d.clip[1].w);
  const glm::dvec3 p2(d.clip[2].x, d.clip[2].y, d.clip[2].w);
  const glm::dvec3 n = glm::cross(p1 - p0, p2 - p0);
  const double e = glm::dot(n, p0);
  // The plane through the eye (seen edge on) covers no pixel's interior: skip it.
  const double scale = glm::length(n) * std::max({glm::length(p0), glm::length(p1), glm::length(p2)});
  if (!(std::abs(e) > 1e-12 * scale)) return d;
  const double w = projection.width, h = projection.height;
  d.a = 2.0 * n.x / (w * e);
  d.b = -2.0 * n.y / (h * e);
  d.c = (-n.x + n.y + n.z) / e;
  d.valid = true;
  return d;
}

TileBins bin_triangles(const TileGrid& grid, const Scene& scene, const Projection& projection) {
  return bin_items(grid, scene.triangle_count(), [&](std::size_t t, auto&& emit) {
    const DrawTriangle d = prepare_triangle(scene, projection, t);
    if (!d.valid) return;
    const ScreenPolygon polygon = make_screen_polygon(projection, d.clip);
    if (polygon.empty()) return;
    for (int ty = grid.row_of(polygon.y0); ty <= grid.row_of(polygon.y1); ++ty) {
      for (int tx = grid.column_of(polygon.x0); tx <= grid.column_of(polygon.x1); ++tx) emit(ty * grid.columns + tx);
    }
  });
}

}  // namespace exao::raster
