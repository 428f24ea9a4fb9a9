#pragma once
// Stereo consistency (seed 003, Shi, Billeter, Eisemann 2022, Sec. 4.1): a left pixel's AO
// against the right view's AO, bilinearly interpolated where the left pixel's point lands,
// E(p) = |A(p) - I(p)|, over the pixels both eyes see. "Both see" is their reverse reprojection
// with back-check (the nearest right pixel, projected back, within one pixel of p) and normal
// check (the four right pixels the interpolation reads have normals within 6 degrees of p's).

#include <array>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "core/camera.h"
#include "ssao/view.h"

namespace exao::ssao {

/// Parallel left and right eyes at eye -+ ipd/2 along the camera's right axis (ipd > 0, world units).
[[nodiscard]] std::pair<Camera, Camera> stereo_cameras(const Camera& camera, double ipd);

/// The left pixels visible in both views, and the four right pixels and bilinear weights each reads.
struct Correspondence {
  std::vector<std::uint32_t> left;             // left pixel
  std::vector<std::array<std::uint32_t, 4>> right;
  std::vector<std::array<float, 4>> weight;
  std::size_t left_visible = 0;                // left pixels that see a triangle
};

[[nodiscard]] Correspondence correspond(const View& left, const View& right);

struct Inconsistency {
  std::size_t pixels = 0;   // pixels compared
  double share = 0.0;       // of the left pixels that see a triangle
  double mean = 0.0;        // mean E
  double rmse = 0.0;
  double within_255 = 0.0;  // share with E <= 1/255
};

[[nodiscard]] Inconsistency inconsistency(const Correspondence& c, std::span<const float> left_ao,
                                          std::span<const float> right_ao);

}  // namespace exao::ssao
