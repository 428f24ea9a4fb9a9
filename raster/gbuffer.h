#pragma once
// exao::raster::rasterize_gbuffer: primary visibility by software rasterization (paper Sec. 4,
// step 1), the `raster` method's replacement for Embree's primary rays. Every scene triangle,
// either face, is clipped in homogeneous space (near plane and guard band), snapped to 1/4096
// pixel and drawn with the top-left fill rule and a depth buffer, in screen tiles on TBB threads.
// Its receivers follow core/pixel_receivers.h: the hit point of the pixel-centre ray on the
// visible triangle, so they equal Embree's wherever the visible triangle is the same.

#include <cstdint>
#include <limits>
#include <vector>

#include "core/camera.h"
#include "core/pixel_receivers.h"
#include "core/scene.h"

namespace exao::raster {

inline constexpr std::uint32_t kNoTriangle = std::numeric_limits<std::uint32_t>::max();

/// Near clip plane of primary visibility, as a fraction of the scene's size (the largest
/// coordinate magnitude of the scene and the eye plus the scene's diagonal): surfaces nearer the
/// eye than this are not seen (Embree's rays start at 0; no test scene comes that close).
inline constexpr double kNearFraction = 1e-6;

struct GBuffer {
  int width = 0, height = 0;
  double near = 0.0;                     // the near plane used, world units
  std::vector<std::uint32_t> triangle;   // per pixel (y * width + x): visible triangle, or kNoTriangle
  std::vector<double> inverse_depth;     // per pixel: 1 / view depth at the pixel centre; 0 where none
};

/// The visible triangle at every pixel centre of a width x height image of `camera` (each in
/// 1 .. 16384). Where two triangles are at exactly the same depth the lower index wins, so the
/// result does not depend on the thread count.
[[nodiscard]] GBuffer rasterize_gbuffer(const Scene& scene, const Camera& camera, int width, int height);

/// The receivers of a G-buffer: for each pixel that sees a triangle, in pixel order, the
/// distance to the triangle's plane along pixel_ray, and pixel_receiver of that.
[[nodiscard]] PixelReceivers gbuffer_receivers(const Scene& scene, const Camera& camera, const GBuffer& gbuffer);

/// rasterize_gbuffer and gbuffer_receivers: the `raster` method's pixel receivers.
[[nodiscard]] PixelReceivers raster_pixel_receivers(const Scene& scene, const Camera& camera, int width, int height);

/// The scene's size for the near plane and float slack: max |coordinate| of the scene's bounds
/// and of `eye`, plus the bounds' diagonal.
[[nodiscard]] double scene_scale(const Scene& scene, const glm::vec3& eye);

}  // namespace exao::raster
