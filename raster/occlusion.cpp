#include "raster/occlusion.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include <tbb/combinable.h>
#include <tbb/parallel_for.h>

#include "core/check.h"
#include "core/mask.h"
#include "lut/float_mode.h"
#include "raster/fragment_tests.h"
#include "raster/gbuffer.h"
#include "raster/influence_volume.h"
#include "raster/projection.h"
#include "raster/rasterizer.h"
#include "raster/screen_polygon.h"
#include "raster/tiles.h"

namespace exao::raster {
namespace {

// What the fragments of a run read, per receiver (index into PixelReceivers::receivers), and
// per pixel for the vectorised first tests (NaN where no receiver: every comparison fails).
struct Receivers {
  std::vector<std::int32_t> of_pixel;  // receiver of each pixel, or -1
  std::vector<Frame> frame;            // the receiver frame: origin p', tilted normal, basis
  std::vector<float> depth;            // view depth of p'
  std::vector<glm::vec3> from_eye;     // p' - eye
  std::vector<float> pixel_x, pixel_y, pixel_z, pixel_depth;  // p' - eye and depth, per pixel
};

// The receivers of a tile (or of a tile's row), in bounds, for culling them all at once: their
// view-depth range and the box of their ray origins.
struct TileBounds {
  float lo = std::numeric_limits<float>::infinity();
  float hi = -std::numeric_limits<float>::infinity();
  glm::vec3 box_lo{std::numeric_limits<float>::infinity()};
  glm::vec3 box_hi{-std::numeric_limits<float>::infinity()};
  [[nodiscard]] bool empty() const { return lo > hi; }
  // Squared distance from `p` to the box, in double (exact enough next to the slack).
  [[nodiscard]] double distance2(const glm::vec3& p) const {
    const glm::dvec3 q(p);
    const glm::dvec3 d = glm::max(glm::max(glm::dvec3(box_lo) - q, q - glm::dvec3(box_hi)), glm::dvec3(0.0));
    return glm::dot(d, d);
  }
  void extend(float depth, const glm::vec3& origin) {
    lo = std::min(lo, depth);
    hi = std::max(hi, depth);
    box_lo = glm::min(box_lo, origin);
    box_hi = glm::max(box_hi, origin);
  }
  // Whether a receiver here may be inside `volume` and pass tests 1 and 2: else all of them
  // would fail (the volume holds every receiver the triangle's mask needs, so its deepest point
  // bounds their depth).
  [[nodiscard]] bool may_reach(const InfluenceVolume& volume, float slack) const {
    return !empty() && volume.max_depth >= double(lo) - double(slack) &&
           volume.cull.near_depth - hi <= volume.cull.depth_reach &&
           distance2(volume.cull.centre) <= double(volume.cull.sphere_reach2);
  }
};

// The screen polygons of a volume's far faces.
struct VolumeRaster {
  std::array<PolygonRaster, InfluenceVolume::kMaxFaces> face;
  std::array<bool, InfluenceVolume::kMaxFaces> valid{};
  int x0 = std::numeric_limits<int>::max(), y0 = std::numeric_limits<int>::max(), x1 = -1, y1 = -1;

  void setup(const InfluenceVolume& volume, const Projection& projection) {
    for (int f = 0; f < volume.face_count; ++f) {
      const auto& face_ref = volume.face[static_cast<std::size_t>(f)];
      std::array<ClipVertex, ScreenPolygon::kMaxInput> clip;
      for (int i = 0; i < face_ref.count; ++i) {
        clip[static_cast<std::size_t>(i)] = volume.clip[volume.index[static_cast<std::size_t>(face_ref.first + i)]];
      }
      PolygonRaster& r = face[static_cast<std::size_t>(f)];
      valid[static_cast<std::size_t>(f)] = r.setup(make_screen_polygon(projection, {clip.data(), face_ref.count}));
      if (!valid[static_cast<std::size_t>(f)]) continue;
      x0 = std::min(x0, r.x0());
      y0 = std::min(y0, r.y0());
      x1 = std::max(x1, r.x1());
      y1 = std::max(y1, r.y1());
    }
  }
  [[nodiscard]] bool empty() const { return x0 > x1 || y0 > y1; }
};

// The volume parameters of triangle t: its r_max in place of r (paper Sec. 4.3).
VolumeParams params_of(const VolumeParams& base, std::span<const DistanceRange> ranges, std::uint32_t t) {
  if (ranges.empty() || !(ranges[t].r_max < base.radius)) return base;
  VolumeParams p = base;
  p.grow = base.grow - base.radius + ranges[t].r_max;
  p.radius = ranges[t].r_max;
  return p;
}

static_assert(TileGrid::kTileSize <= 64, "a tile row's pixels must fit a 64-bit mask");

template <int Bits, bool Stats>
class Renderer {
 public:
  Renderer(const lut::TriangleSet& triangles, const lut::MaskEngine& engine, const Projection& projection,
           const VolumeParams& params, const Receivers& receivers, const std::vector<TileBounds>& row_bounds,
           int columns, bool sphere_mask_cull, std::span<const DistanceRange> ranges, std::vector<Mask<Bits>>& buffers)
      : triangles_(triangles),
        engine_(engine),
        projection_(projection),
        params_(params),
        receivers_(receivers),
        row_bounds_(row_bounds),
        columns_(columns),
        buffers_(buffers),
        all_(engine.all_rays<Bits>()),
        sphere_mask_cull_(sphere_mask_cull),
        ranges_(ranges),
        eye_(projection.eye) {}

  // Draws the volume of triangle t into the tile [tx0, tx1] x [ty0, ty1].
  void draw(std::uint32_t t, int tx0, int ty0, int tx1, int ty1, RasterStats& stats) {
    InfluenceVolume volume;
    if (!build_volume(triangles_, t, params_of(params_, ranges_, t), projection_, volume)) return;
    // The tile's rows where some receiver may need the triangle (all of them when counting).
    std::uint64_t rows = 0;
    const int column = tx0 / TileGrid::kTileSize;
    for (int y = ty0; y <= ty1; ++y) {
      if (Stats || row_bounds_[static_cast<std::size_t>(y * columns_ + column)].may_reach(volume, params_.slack)) {
        rows |= std::uint64_t{1} << (y - ty0);
      }
    }
    if (rows == 0) return;
    VolumeRaster raster;
    raster.setup(volume, projection_);
    ++stats.tile_volumes;
    for (int f = 0; f < volume.face_count; ++f) {
      if (!raster.valid[static_cast<std::size_t>(f)]) continue;
      const PolygonRaster& face = raster.face[static_cast<std::size_t>(f)];
      const DepthPlane& depth = volume.face[static_cast<std::size_t>(f)].depth;
      const bool exclude = f == 1 && volume.exclude_first && raster.valid[0];
      const int y_end = std::min(ty1, face.y1());
      for (int y = std::max(ty0, face.y0()); y <= y_end; ++y) {
        if (!(rows >> (y - ty0) & 1)) continue;
        if (!exclude) {
          face.spans(y, tx0, tx1, [&](int xa, int xb) { shade_span(t, volume.cull, depth, y, xa, xb, 0, stats); });
          continue;
        }
        // The billboard's second polygon skips the first one's pixels (bit x - tx0 of `first`).
        std::uint64_t first = 0;
        raster.face[0].spans(y, tx0, tx1, [&](int xa, int xb) {
          for (int x = xa; x <= xb; ++x) first |= std::uint64_t{1} << (x - tx0);
        });
        face.spans(y, tx0, tx1, [&](int xa, int xb) { shade_span(t, volume.cull, depth, y, xa, xb, first >> (xa - tx0), stats); });
      }
    }
  }

 private:
  // Shades pixels xa..xb of row y, but those whose bit is set in `skip` (bit 0: pixel xa).
  void shade_span(std::uint32_t t, const TriangleCull& cull, const DepthPlane& depth, int y, int xa, int xb,
                  std::uint64_t skip, RasterStats& stats) {
    const std::size_t row = static_cast<std::size_t>(y) * static_cast<std::size_t>(projection_.width);
    if constexpr (Stats) {
      // Every fragment counted at every stage.
      for (int x = xa; x <= xb; ++x, skip >>= 1) {
        if (skip & 1) continue;
        ++stats.fragments;
        const std::int32_t r = receivers_.of_pixel[row + static_cast<std::size_t>(x)];
        if (r < 0) continue;
        const auto i = static_cast<std::size_t>(r);
        if (!passes_depth_test(depth, receivers_.from_eye[i], params_.slack)) continue;
        const int passed = fragment_tests(cull, receivers_.frame[i], receivers_.depth[i]);
        ++stats.depth_passed;
        stats.far_depth_passed += passed >= 1;
        stats.sphere_passed += passed >= 2;
        stats.facing_passed += passed >= 3;
        stats.plane_passed += passed >= 4;
        stats.horizon_passed += passed >= 5;
        if (passed == 5) accumulate(t, i, stats);
      }
    } else {
      // The depth test and tests 1 and 2 for the whole span at once, in a loop the compiler
      // vectorises (per-pixel arrays, p' - eye against centre - eye: the same tests up to
      // rounding far below the slack); the survivors run all five tests and the mask.
      const int n = xb - xa + 1;
      const std::size_t base = row + static_cast<std::size_t>(xa);
      const float* px = receivers_.pixel_x.data() + base;
      const float* py = receivers_.pixel_y.data() + base;
      const float* pz = receivers_.pixel_z.data() + base;
      const float* pd = receivers_.pixel_depth.data() + base;
      const glm::vec3 centre = cull.centre - eye_;
      const float depth_limit = depth.h + params_.slack;
      const float nearest = cull.near_depth - cull.depth_reach;
      std::uint8_t pass[TileGrid::kTileSize];
      for (int k = 0; k < n; ++k) {
        const float dx = px[k] - centre.x, dy = py[k] - centre.y, dz = pz[k] - centre.z;
        const bool behind = depth.m.x * px[k] + depth.m.y * py[k] + depth.m.z * pz[k] <= depth_limit;
        const bool near = pd[k] >= nearest;
        const bool sphere = dx * dx + dy * dy + dz * dz <= cull.sphere_reach2;
        pass[k] = static_cast<std::uint8_t>(behind & near & sphere);
      }
      for (int k = 0; k < n; ++k, skip >>= 1) {
        if (!pass[k] || (skip & 1)) continue;
        const auto i = static_cast<std::size_t>(receivers_.of_pixel[base + static_cast<std::size_t>(k)]);
        if (fragment_tests(cull, receivers_.frame[i], receivers_.depth[i]) == 5) accumulate(t, i, stats);
      }
    }
  }

  // A fragment that passed the five tests: OR the triangle's mask into receiver i's buffer.
  void accumulate(std::uint32_t t, std::size_t i, RasterStats& stats) {
    Mask<Bits>& buffer = buffers_[i];
    if (buffer == all_) {
      if constexpr (Stats) ++stats.full_skipped;
      return;
    }
    const Frame& frame = receivers_.frame[i];
    // Only the clusters of rays that can still change the buffer are computed (lut/mask_engine.h):
    // those with an open ray, and among them those the sphere's mask reaches.
    std::uint64_t clusters = lut::open_clusters(buffer, engine_.samples());
    if (sphere_mask_cull_) {
      // The mask of the triangle's bounding sphere with the node margin holds the triangle's
      // mask (lut/sphere_test.h, nesting): when it adds no ray, neither does the triangle.
      const Mask<Bits> reach = engine_.region_mask<Bits>(frame.to_local(triangles_.centre[t]), triangles_.radius[t],
                                                         lut::kNodeMargin, clusters);
      const Mask<Bits> wanted = and_not(reach, buffer);
      if (wanted.none()) {
        ++stats.sphere_mask_skipped;
        return;
      }
      clusters = lut::occupied_clusters(wanted);
    }
    const Mask<Bits> mask = ranges_.empty() ? engine_.triangle_mask<Bits>(triangles_, t, frame, clusters)
                                            : range_mask<Bits>(engine_, triangles_, t, frame, ranges_[t], clusters);
    ++stats.masks;
    if (mask.any()) {
      ++stats.masks_nonempty;
      buffer |= mask;
    }
  }

  const lut::TriangleSet& triangles_;
  const lut::MaskEngine& engine_;
  const Projection& projection_;
  const VolumeParams& params_;
  const Receivers& receivers_;
  const std::vector<TileBounds>& row_bounds_;  // per tile row: row_bounds_[y * columns_ + tile column]
  const int columns_;
  std::vector<Mask<Bits>>& buffers_;
  const Mask<Bits> all_;
  const bool sphere_mask_cull_;
  const std::span<const DistanceRange> ranges_;
  const glm::vec3 eye_;
};

template <int Bits, bool Stats>
void render(const lut::TriangleSet& triangles, const lut::MaskEngine& engine, const Projection& projection,
            const VolumeParams& params, const Receivers& receivers, bool sphere_mask_cull,
            std::span<const DistanceRange> ranges, MaskSet& masks, RasterStats& stats, const ProgressCallback& progress) {
  const TileGrid grid(projection.width, projection.height);
  const std::size_t receiver_count = receivers.frame.size();

  // The receivers' bounds per tile and per tile row.
  std::vector<TileBounds> tile_bounds(static_cast<std::size_t>(grid.count()));
  std::vector<TileBounds> row_bounds(static_cast<std::size_t>(projection.height * grid.columns));
  for (int y = 0; y < projection.height; ++y) {
    for (int x = 0; x < projection.width; ++x) {
      const std::int32_t r = receivers.of_pixel[static_cast<std::size_t>(y) * static_cast<std::size_t>(projection.width) + static_cast<std::size_t>(x)];
      if (r < 0) continue;
      const auto i = static_cast<std::size_t>(r);
      tile_bounds[static_cast<std::size_t>(grid.row_of(y) * grid.columns + grid.column_of(x))].extend(receivers.depth[i], receivers.frame[i].origin);
      row_bounds[static_cast<std::size_t>(y * grid.columns + grid.column_of(x))].extend(receivers.depth[i], receivers.frame[i].origin);
    }
  }

  // Bin every volume to the tiles it may draw into (paper step 3a: one shape per triangle).
  tbb::combinable<RasterStats> local;
  const TileBins bins = bin_items(grid, triangles.size(), [&](std::size_t t, auto&& emit) {
    const lut::FlushDenormals flush;  // build_volume as in the tiles below, on any thread
    RasterStats& mine = local.local();
    InfluenceVolume volume;
    if (!build_volume(triangles, static_cast<std::uint32_t>(t), params_of(params, ranges, static_cast<std::uint32_t>(t)),
                      projection, volume)) {
      ++mine.volumes_off;
      return;
    }
    switch (volume.shape) {
      case VolumeShape::Prism: ++mine.prisms; break;
      case VolumeShape::Billboard: ++mine.billboards; break;
      case VolumeShape::Box: ++mine.boxes; break;
    }
    VolumeRaster raster;
    raster.setup(volume, projection);
    bool any = false;
    if (!raster.empty()) {
      for (int ty = grid.row_of(raster.y0); ty <= grid.row_of(raster.y1); ++ty) {
        for (int tx = grid.column_of(raster.x0); tx <= grid.column_of(raster.x1); ++tx) {
          const int tile = ty * grid.columns + tx;
          const TileBounds& b = tile_bounds[static_cast<std::size_t>(tile)];
          if (b.empty()) continue;
          if (!Stats && !b.may_reach(volume, params.slack)) continue;
          emit(tile);
          any = true;
        }
      }
    }
    if (!any) ++mine.volumes_off;
  });

  // Draw the tiles (steps 3b-3d).
  std::vector<Mask<Bits>> buffers(receiver_count);
  ProgressCounter counter(progress, static_cast<std::size_t>(grid.count()));
  tbb::parallel_for(0, grid.count(), [&](int tile) {
    const lut::FlushDenormals flush;  // the same float mode on every thread (lut/float_mode.h)
    RasterStats& mine = local.local();
    Renderer<Bits, Stats> renderer(triangles, engine, projection, params, receivers, row_bounds, grid.columns,
                                   sphere_mask_cull, ranges, buffers);
    int tx0 = 0, ty0 = 0, tx1 = 0, ty1 = 0;
    grid.rect(tile, tx0, ty0, tx1, ty1);
    for (std::size_t i = bins.offset[static_cast<std::size_t>(tile)]; i < bins.offset[static_cast<std::size_t>(tile) + 1]; ++i) {
      renderer.draw(bins.items[i], tx0, ty0, tx1, ty1, mine);
    }
    counter.add(1);
  });
  local.combine_each([&](const RasterStats& s) { stats += s; });

  tbb::parallel_for(std::size_t{0}, receiver_count, [&](std::size_t i) { store(buffers[i], masks.row(i)); });
}

}  // namespace

RasterResult occlusion(const PixelReceivers& pixels, const Scene& scene, const lut::TriangleSet& triangles,
                       const lut::MaskEngine& engine, const Camera& camera, const RasterOptions& options,
                       const ProgressCallback& progress) {
  if (options.ranges.empty()) {
    EXAO_CHECK_EQ(triangles.size(), scene.triangle_count());
  } else {
    EXAO_CHECK_EQ(options.ranges.size(), triangles.size());
  }
  EXAO_CHECK_GT(options.alpha, 0.0f);
  RasterResult result;
  result.pixels = pixels;
  const std::size_t count = pixels.receivers.size();
  result.masks = MaskSet(count, engine.samples());
  result.stats.receivers = count;
  result.stats.triangles = triangles.size();
  if (count == 0 || triangles.size() == 0) return result;

  const int width = pixels.width, height = pixels.height;
  const double scale = scene_scale(scene, camera.eye);
  const Projection view = Projection::make(camera, width, height, 1.0);

  Receivers receivers;
  receivers.of_pixel.assign(static_cast<std::size_t>(width) * static_cast<std::size_t>(height), -1);
  receivers.frame.resize(count);
  receivers.depth.resize(count);
  receivers.from_eye.resize(count);
  const std::size_t pixel_count = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  for (auto* v : {&receivers.pixel_x, &receivers.pixel_y, &receivers.pixel_z, &receivers.pixel_depth}) {
    v->assign(pixel_count, std::numeric_limits<float>::quiet_NaN());
  }
  std::vector<double> point_depth(count);
  for (std::size_t i = 0; i < count; ++i) {
    EXAO_CHECK_LT(pixels.pixel[i], receivers.of_pixel.size());
    EXAO_CHECK_LT(receivers.of_pixel[pixels.pixel[i]], 0);  // at most one receiver per pixel
    receivers.of_pixel[pixels.pixel[i]] = static_cast<std::int32_t>(i);
  }
  tbb::parallel_for(std::size_t{0}, count, [&](std::size_t i) {
    const lut::FlushDenormals flush;
    const Frame frame = engine.rays().frame(pixels.receivers[i]);
    receivers.frame[i] = frame;
    receivers.depth[i] = static_cast<float>(view.to_clip(frame.origin).w);
    receivers.from_eye[i] = frame.origin - camera.eye;
    point_depth[i] = view.to_clip(pixels.receivers[i].position).w;
    const std::size_t p = pixels.pixel[i];
    receivers.pixel_x[p] = receivers.from_eye[i].x;
    receivers.pixel_y[p] = receivers.from_eye[i].y;
    receivers.pixel_z[p] = receivers.from_eye[i].z;
    receivers.pixel_depth[p] = receivers.depth[i];
  });

  // The volumes' near plane: in front of every receiver point (they are on pixel rays in front
  // of the eye), so clipping keeps every far-face fragment a receiver needs.
  const double nearest = *std::min_element(point_depth.begin(), point_depth.end());
  double near = 0.5 * std::min(kNearFraction * scale, nearest);
  if (!(near > 0.0)) near = 1e-9 * scale;  // a receiver at or behind the eye: not a pixel receiver
  const Projection projection = Projection::make(camera, width, height, near);
  VolumeParams params = make_volume_params(engine.rays(), scale, options.alpha, near);
  params.grow -= options.test_shrink * params.radius;

  with_mask_bits(engine.samples(), [&](auto bits) {
    constexpr int Bits = decltype(bits)::value;
    if (options.stats) {
      render<Bits, true>(triangles, engine, projection, params, receivers, options.sphere_mask_cull, options.ranges, result.masks, result.stats, progress);
    } else {
      render<Bits, false>(triangles, engine, projection, params, receivers, options.sphere_mask_cull, options.ranges, result.masks, result.stats, progress);
    }
  });
  return result;
}

RasterResult occlusion(const Scene& scene, const lut::TriangleSet& triangles, const lut::MaskEngine& engine,
                       const Camera& camera, int width, int height, const RasterOptions& options,
                       const ProgressCallback& progress) {
  return occlusion(raster_pixel_receivers(scene, camera, width, height), scene, triangles, engine, camera, options,
                   progress);
}

}  // namespace exao::raster
