#pragma once
// One scene triangle set up for drawing, and the binning of a scene's triangles into screen
// tiles: shared by the G-buffer (raster/gbuffer.h) and the SSAO fragment buffer
// (ssao/fragment_buffer.h), whose first fragment at a pixel must be the G-buffer's bit for bit.

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>

#include "core/scene.h"
#include "raster/projection.h"
#include "raster/rasterizer.h"
#include "raster/screen_polygon.h"
#include "raster/tiles.h"

namespace exao::raster {

/// A scene triangle ready to draw: its clip-space vertices and 1/w as an affine function of the
/// screen position (pixels), 1/w = a px + b py + c, from the plane through the clip vertices.
struct DrawTriangle {
  std::array<ClipVertex, 3> clip;
  double a = 0.0, b = 0.0, c = 0.0;
  bool valid = false;  // false: wholly behind the near plane, or seen edge on (covers no pixel)
};

/// Triangle `t` of `scene` through `projection`.
[[nodiscard]] DrawTriangle prepare_triangle(const Scene& scene, const Projection& projection, std::size_t t);

/// Every valid triangle of `scene`, by index, in each tile its screen polygon's bounds touch.
[[nodiscard]] TileBins bin_triangles(const TileGrid& grid, const Scene& scene, const Projection& projection);

/// Draws the triangles binned to `tile` (bin_triangles), in increasing index: for every pixel of
/// the tile whose centre a triangle covers (the fill rule of raster/rasterizer.h), row by row,
/// `fragment(x, y, t, inverse_depth)` with 1/w at the pixel centre as DrawTriangle gives it.
/// The G-buffer and the fragment buffer draw through this one loop, so that their fragments
/// are the same bit for bit.
template <class Fragment>
void draw_tile(const Scene& scene, const Projection& projection, const TileGrid& grid, const TileBins& bins, int tile,
               Fragment&& fragment) {
  int tx0 = 0, ty0 = 0, tx1 = 0, ty1 = 0;
  grid.rect(tile, tx0, ty0, tx1, ty1);
  for (std::size_t i = bins.offset[static_cast<std::size_t>(tile)]; i < bins.offset[static_cast<std::size_t>(tile) + 1]; ++i) {
    const std::uint32_t t = bins.items[i];
    const DrawTriangle d = prepare_triangle(scene, projection, t);
    PolygonRaster raster;
    if (!raster.setup(make_screen_polygon(projection, d.clip))) continue;
    const int y_end = std::min(ty1, raster.y1());
    for (int y = std::max(ty0, raster.y0()); y <= y_end; ++y) {
      const double py = y + 0.5;
      raster.spans(y, tx0, tx1, [&](int xa, int xb) {
        for (int x = xa; x <= xb; ++x) fragment(x, y, t, d.a * (x + 0.5) + d.b * py + d.c);
      });
    }
  }
}

}  // namespace exao::raster
