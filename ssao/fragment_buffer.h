#pragma once
// exao::ssao::FragmentBuffer: the A-buffer (Carpenter 1984; seed 004): every fragment of every
// triangle at every pixel centre, not only the nearest, sorted front to back. The software
// rasterizer's coverage (raster/rasterizer.h: exact edge functions, top-left rule) and depth
// (1/w interpolated in screen space), so its first fragment is the G-buffer's.

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "core/camera.h"
#include "core/scene.h"

namespace exao::ssao {

struct Fragment {
  float depth = 0.0f;          // view depth (along the camera's forward axis), world units, > 0
  std::uint32_t triangle = 0;  // scene triangle
};

struct FragmentBuffer {
  int width = 0, height = 0;
  std::vector<std::size_t> offset;   // pixel p holds fragments[offset[p] .. offset[p + 1])
  std::vector<Fragment> fragments;   // per pixel, nearest first (ties: lower triangle first)

  [[nodiscard]] std::span<const Fragment> at(std::size_t pixel) const {
    return {fragments.data() + offset[pixel], offset[pixel + 1] - offset[pixel]};
  }
};

/// All fragments of a width x height image of `camera` (each 1 .. 16384), both faces of every
/// triangle, with the G-buffer's near plane.
[[nodiscard]] FragmentBuffer rasterize_fragments(const Scene& scene, const Camera& camera, int width, int height);

}  // namespace exao::ssao
