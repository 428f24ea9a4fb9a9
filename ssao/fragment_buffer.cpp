#include "ssao/fragment_buffer.h"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>

#include <tbb/parallel_for.h>

#include "raster/draw_triangle.h"
#include "raster/gbuffer.h"
#include "raster/projection.h"
#include "raster/rasterizer.h"
#include "raster/screen_polygon.h"
#include "raster/tiles.h"

namespace exao::ssao {
namespace {

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
  const raster::TileBins bins = raster::bin_triangles(grid, scene, projection);

  // Each tile owns its pixels: its fragments are gathered, then sorted by pixel and depth.
  std::vector<std::vector<TileFragment>> tiles(static_cast<std::size_t>(grid.count()));
  tbb::parallel_for(0, grid.count(), [&](int tile) {
    std::vector<TileFragment>& mine = tiles[static_cast<std::size_t>(tile)];
    raster::draw_tile(scene, projection, grid, bins, tile, [&](int x, int y, std::uint32_t t, double inverse_depth) {
      if (!(inverse_depth > 0.0)) return;
      const auto p = static_cast<std::uint32_t>(y * width + x);
      mine.push_back({p, {static_cast<float>(1.0 / inverse_depth), t}});
    });
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
