#pragma once
// exao::raster::Projection: world -> homogeneous clip space -> fixed-point screen, with the same
// pinhole convention as core/camera.h's pixel_ray: the point on the ray through the centre of
// pixel (x, y) projects to screen coordinates (x + 0.5, y + 0.5); y = 0 is the top row.
//
// Clip space is (x, y, w) with w the view depth along the camera's forward axis (no z: depth is
// tested against world-space planes, see raster/influence_volume.h). A point is on screen when
// |x| <= w and |y| <= w. Screen coordinates are snapped to 1/kSubpixel pixel, so edge functions
// are exact in 64-bit integers (raster/rasterizer.h).

#include <cstdint>

#include <glm/glm.hpp>

#include "core/camera.h"

namespace exao::raster {

/// Sub-pixel precision of screen coordinates: 1/4096 pixel. Vertices move by at most 1/8192
/// pixel when snapped; the influence volumes' margin is far larger (raster/influence_volume.h).
inline constexpr int kSubpixelBits = 12;
inline constexpr std::int64_t kSubpixel = std::int64_t{1} << kSubpixelBits;

/// Polygons are clipped to |x|, |y| <= kGuardBand * w (and to w >= near): the clipped edges lie
/// outside the image, where no pixel centre is, and screen coordinates stay below 2^27 subpixels
/// for images up to kMaxImageSize, so the rasterizer's 64-bit edge functions never overflow.
inline constexpr double kGuardBand = 2.0;
inline constexpr int kMaxImageSize = 16384;

/// A vertex in clip space.
struct ClipVertex {
  double x = 0.0, y = 0.0, w = 0.0;
};

/// A screen vertex in fixed point: pixel coordinate * kSubpixel.
struct ScreenVertex {
  std::int64_t x = 0, y = 0;
  friend bool operator==(const ScreenVertex&, const ScreenVertex&) = default;
};

struct Projection {
  // The camera basis exactly as pixel_ray builds it (float), widened to double.
  glm::dvec3 eye{0.0}, right{1.0, 0.0, 0.0}, up{0.0, 1.0, 0.0}, forward{0.0, 0.0, -1.0};
  double kx = 1.0, ky = 1.0;  // x_clip = kx * X_view, y_clip = ky * Y_view: 1 / (tan(yfov/2) * aspect), 1 / tan(yfov/2)
  int width = 0, height = 0;
  double near = 0.0;  // clip plane w >= near, world units, > 0

  /// Projection of `camera` for a width x height image (1 .. kMaxImageSize each) with clip
  /// plane at view depth `near` > 0.
  [[nodiscard]] static Projection make(const Camera& camera, int width, int height, double near);

  [[nodiscard]] ClipVertex to_clip(const glm::dvec3& p) const {
    const glm::dvec3 v = p - eye;
    return {kx * glm::dot(v, right), ky * glm::dot(v, up), glm::dot(v, forward)};
  }
  [[nodiscard]] ClipVertex to_clip(const glm::vec3& p) const { return to_clip(glm::dvec3(p)); }

  /// Screen position of a clip vertex with w > 0, snapped to the subpixel grid.
  [[nodiscard]] ScreenVertex to_screen(const ClipVertex& c) const;

  /// Screen x (pixels, not snapped) of clip x / w, and y likewise: px = (x/w + 1) W / 2,
  /// py = (1 - y/w) H / 2.
  [[nodiscard]] double screen_x(double ndc_x) const { return (ndc_x + 1.0) * 0.5 * width; }
  [[nodiscard]] double screen_y(double ndc_y) const { return (1.0 - ndc_y) * 0.5 * height; }
};

/// The five clip planes, as signed distances of a clip vertex (inside when >= 0): w - near, then
/// the guard band's left, right, bottom and top.
inline constexpr int kClipPlanes = 5;
[[nodiscard]] inline double clip_distance(const Projection& projection, const ClipVertex& v, int plane) {
  switch (plane) {
    case 0: return v.w - projection.near;
    case 1: return kGuardBand * v.w + v.x;
    case 2: return kGuardBand * v.w - v.x;
    case 3: return kGuardBand * v.w + v.y;
    default: return kGuardBand * v.w - v.y;
  }
}

}  // namespace exao::raster
