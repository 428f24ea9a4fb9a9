#include "ssao/fragment_buffer.h"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>

#include <tbb/parallel_for.h>

#include "raster/gbuffer.h"
#include "raster/projection.h"
#include "raster/rasterizer.h"
#include "raster/screen_polygon.h"
#include "raster/tiles.h"

namespace exao::ssao {
namespace {

// As raster/gbuffer.cpp draws a triangle: clip vertices, and 1/w as an affine function of the
// screen position, 1/w = a px + b py + c, from the plane through the clip vertices. Kept in step
// with it so the first fragment is the G-buffer's.
struct DrawTriangle {
  std::array<raster::ClipVertex, 3> clip;
  double a = 0.0, b = 0.0, c = 0.0;
  bool valid = false;
};

DrawTriangle prepare(const Scene& scene, const raster::Projection& projection, std::size_t t) {
  DrawTriangle d;
  for (int k = 0; k < 3; ++k) d.clip[static_cast<std::size_t>(k)] = projection.to_clip(scene.vertices[3 * t + static_cast<std::size_t>(k)]);
  if (d.clip[0].w < projection.near && d.clip[1].w < projection.near && d.clip[2].w < projection.near) return d;
  const glm::dvec3 p0(d.clip[0].x, d.clip[0].y, d.clip[0].w);
  const glm::dvec3 p1(d.clip[1].x, d.clip[1].y, d.clip[1].w);
  const glm::dvec3 p2(d.clip[2].x, d.clip[2].y, d.clip[2].w);
  const glm::dvec3 n = glm::cross(p1 - p0, p2 - p0);
  const double e = glm::dot(n, p0);
  const double scale = glm::length(n) * std::max({glm::length(p0), glm::length(p1), glm::length(p2)});
  if (!(std::abs(e) > 1e-12 * scale)) return d;
  const double w = projection.width, h = projection.height;
  d.a = 2.0 * n.x / (w * e);
  d.b = -2.0 * n.y / (h * e);
  d.c = (-n.x + n.y + n.z) / e;
  d.valid = true;
  return d;
}

struct TileFragment {
  std::uint32_t pixel;
  Fragment fragment;
};

}  // namespace

FragmentBuffer rasterize_fragments(const Scene& scene, const Camera& camera, int width, int height) {
  assert(width >= 1 && height >= 1 && width <= raster::kMaxImageSize && height <= raster::kMaxImageSize);
  FragmentBuffer out;
  out.width = width;
  out.height = height;
  const double near = raster::kNearFraction * raster::scene_scale(scene, camera.eye);
  const raster::Projection projection = raster::Projection::make(camera, width, height, near);
  const raster::TileGrid grid(width, height);
  const raster::TileBins bins = raster::bin_items(grid, scene.triangle_count(), [&](std::size_t t, auto&& emit) {
    const DrawTriangle d = prepare(scene, projection, t);
    if (!d.valid) return;
    const raster::ScreenPolygon polygon = raster::make_screen_polygon(projection, d.clip);
    if (polygon.empty()) return;
    for (int ty = grid.row_of(polygon.y0); ty <= grid.row_of(polygon.y1); ++ty) {
      for (int tx = grid.column_of(polygon.x0); tx <= grid.column_of(polygon.x1); ++tx) emit(ty * grid.columns + tx);
    }
  });

  // Each tile owns its pixels: its fragments are gathered, then sorted by pixel and depth.
  std::vector<std::vector<TileFragment>> tiles(static_cast<std::size_t>(grid.count()));
  tbb::parallel_for(0, grid.count(), [&](int tile) {
    int tx0 = 0, ty0 = 0, tx1 = 0, ty1 = 0;
    grid.rect(tile, tx0, ty0, tx1, ty1);
    std::vector<TileFragment>& mine = tiles[static_cast<std::size_t>(tile)];
    for (std::size_t i = bins.offset[static_cast<std::size_t>(tile)]; i < bins.offset[static_cast<std::size_t>(tile) + 1]; ++i) {
      const std::uint32_t t = bins.items[i];
      const DrawTriangle d = prepare(scene, projection, t);
      raster::PolygonRaster raster;
      if (!raster.setup(raster::make_screen_polygon(projection, d.clip))) continue;
      const int y_end = std::min(ty1, raster.y1());
      for (int y = std::max(ty0, raster.y0()); y <= y_end; ++y) {
        const double py = y + 0.5;
        raster.spans(y, tx0, tx1, [&](int xa, int xb) {
          for (int x = xa; x <= xb; ++x) {
            const double inverse_depth = d.a * (x + 0.5) + d.b * py + d.c;
            if (!(inverse_depth > 0.0)) continue;
            const auto p = static_cast<std::uint32_t>(y * width + x);
            mine.push_back({p, {static_cast<float>(1.0 / inverse_depth), t}});
          }
        });
      }
    }
    std::sort(mine.begin(), mine.end(), [](const TileFragment& a, const TileFragment& b) {
      if (a.pixel != b.pixel) return a.pixel < b.pixel;
      if (a.fragment.depth != b.fragment.depth) return a.fragment.depth < b.fragment.depth;
      return a.fragment.triangle < b.fragment.triangle;
    });
  });

  const std::size_t pixels = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  out.offset.assign(pixels + 1, 0);
  for (const auto& tile : tiles) {
    for (const TileFragment& f : tile) ++out.offset[f.pixel + 1];
  }
  for (std::size_t p = 0; p < pixels; ++p) out.offset[p + 1] += out.offset[p];
  out.fragments.resize(out.offset[pixels]);
  tbb::parallel_for(std::size_t{0}, tiles.size(), [&](std::size_t k) {
    std::size_t run = 0;
    std::uint32_t last = ~0u;
    for (const TileFragment& f : tiles[k]) {
      run = f.pixel == last ? run + 1 : 0;
      last = f.pixel;
      out.fragments[out.offset[f.pixel] + run] = f.fragment;
    }
  });
  return out;
}

}  // namespace exao::ssao
