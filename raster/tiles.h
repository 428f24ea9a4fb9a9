#pragma once
// exao::raster::TileGrid and TileBins: the image cut into square tiles, and for each tile the
// list of primitives (scene triangles, influence volumes) that may cover it. Tiles are the unit
// of parallel work: one task owns a tile's pixels, so depth and occlusion buffers are written
// without atomics, and a tile's buffers stay in cache while its primitives are drawn.

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

namespace exao::raster {

struct TileGrid {
  static constexpr int kTileSize = 32;  // pixels; small enough for 2..64 threads to balance on 512x384

  int width = 0, height = 0;
  int columns = 0, rows = 0;

  TileGrid(int image_width, int image_height)
      : width(image_width),
        height(image_height),
        columns((image_width + kTileSize - 1) / kTileSize),
        rows((image_height + kTileSize - 1) / kTileSize) {}

  [[nodiscard]] int count() const { return columns * rows; }
  [[nodiscard]] int column_of(int x) const { return x / kTileSize; }
  [[nodiscard]] int row_of(int y) const { return y / kTileSize; }
  /// Pixel rectangle of tile k: [x0, x1] x [y0, y1], inclusive.
  void rect(int k, int& x0, int& y0, int& x1, int& y1) const {
    x0 = (k % columns) * kTileSize;
    y0 = (k / columns) * kTileSize;
    x1 = std::min(x0 + kTileSize, width) - 1;
    y1 = std::min(y0 + kTileSize, height) - 1;
  }
};

/// Items per tile, in increasing item order: tile k holds items[offset[k] .. offset[k + 1]).
struct TileBins {
  std::vector<std::size_t> offset;
  std::vector<std::uint32_t> items;

  [[nodiscard]] std::size_t size(int tile) const { return offset[static_cast<std::size_t>(tile) + 1] - offset[static_cast<std::size_t>(tile)]; }
};

/// Bins items 0 .. count-1 in parallel: `visit(item, emit)` calls emit(tile) for every tile the
/// item may cover (any order, no repeats). The order within a tile is the items' order, so the
/// result does not depend on the threads.
template <class Visit>
[[nodiscard]] TileBins bin_items(const TileGrid& grid, std::size_t count, const Visit& visit) {
  using Pair = std::pair<std::uint32_t, std::uint32_t>;  // (tile, item)
  tbb::enumerable_thread_specific<std::vector<Pair>> local;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count, 1024), [&](const tbb::blocked_range<std::size_t>& range) {
    std::vector<Pair>& mine = local.local();
    for (std::size_t i = range.begin(); i < range.end(); ++i) {
      const auto item = static_cast<std::uint32_t>(i);
      visit(i, [&](int tile) { mine.emplace_back(static_cast<std::uint32_t>(tile), item); });
    }
  });
  TileBins bins;
  const auto tiles = static_cast<std::size_t>(grid.count());
  bins.offset.assign(tiles + 1, 0);
  for (const auto& pairs : local) {
    for (const Pair& p : pairs) ++bins.offset[p.first + 1];
  }
  for (std::size_t k = 0; k < tiles; ++k) bins.offset[k + 1] += bins.offset[k];
  bins.items.resize(bins.offset[tiles]);
  std::vector<std::size_t> cursor(bins.offset.begin(), bins.offset.end() - 1);
  for (const auto& pairs : local) {
    for (const Pair& p : pairs) bins.items[cursor[p.first]++] = p.second;
  }
  tbb::parallel_for(std::size_t{0}, tiles, [&](std::size_t k) {
    std::sort(bins.items.begin() + static_cast<std::ptrdiff_t>(bins.offset[k]),
              bins.items.begin() + static_cast<std::ptrdiff_t>(bins.offset[k + 1]));
  });
  return bins;
}

}  // namespace exao::raster
