#pragma once
// exao::ssao::View: one camera's G-buffer as the screen-space methods read it. It comes from the
// raster backend (raster/gbuffer.h), so every method, and the exact AO it is measured against,
// sees the same visible triangle, point and normal at every pixel.

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "core/camera.h"
#include "core/pixel_receivers.h"
#include "core/scene.h"

namespace exao::ssao {

struct View {
  Camera camera;
  int width = 0, height = 0;
  // The camera basis as pixel_ray builds it; tan_half = tan(yfov / 2).
  glm::dvec3 eye{0.0}, right{1.0, 0.0, 0.0}, up{0.0, 1.0, 0.0}, forward{0.0, 0.0, -1.0};
  double tan_half = 1.0, aspect = 1.0;

  /// Per pixel (y * width + x): whether a triangle is seen; its receiver point (world) and unit
  /// normal turned toward the eye; the view depth (along forward, +inf where none); the triangle.
  std::vector<std::uint8_t> valid;
  std::vector<glm::vec3> position;
  std::vector<glm::vec3> normal;
  std::vector<float> depth;
  std::vector<std::uint32_t> triangle;
  /// The same receivers in pixel order (keys: pixel index), for the exact AO.
  PixelReceivers receivers;

  [[nodiscard]] std::size_t pixel_count() const { return valid.size(); }
  /// Continuous pixel coordinates of a world point in front of the eye (the centre of pixel
  /// (x, y) is (x + 1/2, y + 1/2)); depth <= 0 gives a point off screen.
  [[nodiscard]] glm::dvec2 project(const glm::dvec3& p) const {
    const glm::dvec3 v = p - eye;
    const double w = glm::dot(v, forward);
    if (!(w > 0.0)) return {-1e30, -1e30};
    const double sx = glm::dot(v, right) / (w * tan_half * aspect);
    const double sy = glm::dot(v, up) / (w * tan_half);
    return {(sx + 1.0) * 0.5 * width, (1.0 - sy) * 0.5 * height};
  }
  /// Continuous coordinates of the centre of `pixel`.
  [[nodiscard]] glm::dvec2 centre(std::size_t pixel) const {
    return {static_cast<double>(pixel % static_cast<std::size_t>(width)) + 0.5,
            static_cast<double>(pixel / static_cast<std::size_t>(width)) + 0.5};
  }
  /// The pixel holding continuous coordinates c, or -1 outside the image.
  [[nodiscard]] std::int64_t pixel_at(const glm::dvec2& c) const {
    if (!(c.x >= 0.0 && c.y >= 0.0 && c.x < width && c.y < height)) return -1;
    return static_cast<std::int64_t>(c.y) * width + static_cast<std::int64_t>(c.x);
  }
  /// The point at view depth `w` on the centre ray of `pixel`.
  [[nodiscard]] glm::dvec3 point_at(std::size_t pixel, double w) const {
    const int x = static_cast<int>(pixel % static_cast<std::size_t>(width));
    const int y = static_cast<int>(pixel / static_cast<std::size_t>(width));
    const double sx = (2.0 * (x + 0.5) / width - 1.0) * tan_half * aspect;
    const double sy = (1.0 - 2.0 * (y + 0.5) / height) * tan_half;
    return eye + w * (forward + sx * right + sy * up);
  }
  /// The (unnormalised) direction of the ray through continuous pixel coordinates c; its
  /// component along forward is 1, so eye + w * ray(c) is at view depth w.
  [[nodiscard]] glm::dvec3 ray(const glm::dvec2& c) const {
    const double sx = (2.0 * c.x / width - 1.0) * tan_half * aspect;
    const double sy = (1.0 - 2.0 * c.y / height) * tan_half;
    return forward + sx * right + sy * up;
  }
  /// Where the ray through c meets the plane through `on_plane` with normal `normal`: the
  /// surface a pixel holds, extended from its centre to a point c inside it (a plane's points
  /// along a screen line then lie exactly on one line in space). `on_plane` itself when the ray
  /// grazes the plane, i.e. when the view depth would change by more than a factor of 2.
  [[nodiscard]] glm::dvec3 point_on_plane(const glm::dvec2& c, const glm::dvec3& on_plane, const glm::dvec3& plane_normal) const {
    const glm::dvec3 d = ray(c);
    const double along = glm::dot(d, plane_normal);
    const double w0 = glm::dot(on_plane - eye, forward);
    if (along == 0.0) return on_plane;
    const double w = glm::dot(on_plane - eye, plane_normal) / along;
    if (!(w > 0.5 * w0 && w < 2.0 * w0)) return on_plane;
    return eye + w * d;
  }
  /// Pixels per world unit at view depth w (a length r at depth w covers r * this pixels).
  [[nodiscard]] double pixels_per_unit(double w) const { return 0.5 * height / (tan_half * w); }
};

/// A View of `camera` with its projection only (the basis, tan_half, aspect, size) and no
/// pixels: for a camera whose depths come from elsewhere (seed 000's secondary view).
[[nodiscard]] View view_basis(const Camera& camera, int width, int height);

/// The G-buffer of a width x height image of `camera` (raster::rasterize_gbuffer and
/// gbuffer_receivers), as a View.
[[nodiscard]] View make_view(const Scene& scene, const Camera& camera, int width, int height);

}  // namespace exao::ssao
