#include "raster/gbuffer.h"

#include <algorithm>
#include <array>
#include <cmath>

#include <tbb/parallel_for.h>

#include "core/check.h"
#include "raster/draw_triangle.h"
#include "raster/projection.h"
#include "raster/rasterizer.h"
#include "raster/screen_polygon.h"
#include "raster/tiles.h"

namespace exao::raster {

double scene_scale(const Scene& scene, const glm::vec3& eye) {
  const Bounds bounds = scene.bounds();
  double m = std::max({std::abs(eye.x), std::abs(eye.y), std::abs(eye.z)});
  if (!bounds.empty()) {
    for (const glm::vec3& p : {bounds.lo, bounds.hi}) m = std::max({m, double(std::abs(p.x)), double(std::abs(p.y)), double(std::abs(p.z))});
    m += bounds.diagonal();
  }
  return std::max(m, 1e-30);
}

GBuffer rasterize_gbuffer(const Scene& scene, const Camera& camera, int width, int height) {
  EXAO_CHECK_GE(width, 1);
  EXAO_CHECK_GE(height, 1);
  EXAO_CHECK_LE(width, kMaxImageSize);
  EXAO_CHECK_LE(height, kMaxImageSize);
  GBuffer g;
  g.width = width;
  g.height = height;
  g.near = kNearFraction * scene_scale(scene, camera.eye);
  const std::size_t pixels = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  g.triangle.assign(pixels, kNoTriangle);
  g.inverse_depth.assign(pixels, 0.0);
  const Projection projection = Projection::make(camera, width, height, g.near);
  const TileGrid grid(width, height);

  const TileBins bins = bin_triangles(grid, scene, projection);

  tbb::parallel_for(0, grid.count(), [&](int tile) {
    draw_tile(scene, projection, grid, bins, tile, [&](int x, int y, std::uint32_t t, double inverse_depth) {
      const std::size_t p = static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x);
      // Nearest wins (largest 1/w); items come in increasing index, so a tie keeps the lower.
      if (inverse_depth > g.inverse_depth[p]) {
        g.inverse_depth[p] = inverse_depth;
        g.triangle[p] = t;
      }
    });
  });
  return g;
}

PixelReceivers gbuffer_receivers(const Scene& scene, const Camera& camera, const GBuffer& gbuffer) {
  PixelReceivers result;
  result.width = gbuffer.width;
  result.height = gbuffer.height;
  const std::size_t pixels = gbuffer.triangle.size();
  std::size_t visible = 0;
  for (const std::uint32_t t : gbuffer.triangle) visible += t != kNoTriangle;
  result.receivers.resize(visible);
  result.pixel.resize(visible);
  result.triangle.resize(visible);
  std::size_t next = 0;
  for (std::size_t p = 0; p < pixels; ++p) {
    if (gbuffer.triangle[p] == kNoTriangle) continue;
    result.pixel[next] = static_cast<std::uint32_t>(p);
    result.triangle[next] = gbuffer.triangle[p];
    ++next;
  }
  tbb::parallel_for(std::size_t{0}, visible, [&](std::size_t i) {
    const std::uint32_t p = result.pixel[i];
    const std::uint32_t t = result.triangle[i];
    const int x = static_cast<int>(p % static_cast<std::uint32_t>(gbuffer.width));
    const int y = static_cast<int>(p / static_cast<std::uint32_t>(gbuffer.width));
    const glm::vec3 direction = pixel_ray(camera, gbuffer.width, gbuffer.height, x, y);
    const auto tri = scene.triangle(t);
    // The pixel-centre ray against the triangle's plane (DESIGN.md: the receiver is where the
    // pixel-centre ray meets the visible triangle).
    const glm::vec3 normal = glm::cross(tri[1] - tri[0], tri[2] - tri[0]);
    float distance = glm::dot(normal, tri[0] - camera.eye) / glm::dot(normal, direction);
    if (!(distance > 0.0f && std::isfinite(distance))) {
      // Grazing: the rasterised depth instead (w is the depth along forward).
      distance = static_cast<float>(1.0 / gbuffer.inverse_depth[p]) / glm::dot(direction, camera.forward);
    }
    result.receivers[i] = pixel_receiver(scene, camera, gbuffer.width, gbuffer.height, p, t, distance);
  });
  return result;
}

PixelReceivers raster_pixel_receivers(const Scene& scene, const Camera& camera, int width, int height) {
  return gbuffer_receivers(scene, camera, rasterize_gbuffer(scene, camera, width, height));
}

}  // namespace exao::raster
