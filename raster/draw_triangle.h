#pragma once
// One scene triangle set up for drawing, and the binning of a scene's triangles into screen
// tiles: shared by the G-buffer (raster/gbuffer.h) and the SSAO fragment buffer
// (ssao/fragment_buffer.h), whose first fragment at a pixel must be the G-buffer's bit for bit.

#include <array>
#include <cstddef>

#include "core/scene.h"
#include "raster/projection.h"
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

}  // namespace exao::raster
