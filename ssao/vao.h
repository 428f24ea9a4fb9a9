#pragma once
// exao::ssao::vao: volumetric AO as seed 001 builds it on Loos & Sloan's volumetric obscurance
// (2010). Eight line samples on a disc of radius r facing the eye, angles 2 pi i / 8 + xi (xi per
// pixel of a 4 x 4 block, over a full turn: see vao_sample), radii sqrt(1 - psi_i^(2/3)) for the base-2 van der Corput numbers
// psi = 1/16, 9/16, ... 15/16 (their Eq. 4-5). Each line crosses the unit ball over a column of
// height h = 2 sqrt(1 - rho^2); only the part above the tangent plane counts (hemisphere
// sampling), AO = 2/8 sum u_i / h_i with u_i the unoccupied length in front of the depth sample
// (Eq. 6-7, doubled because half the ball is ignored). Their halo model (Sec. 3.3, Fig. 4, Eq. 8):
// a surface in front of the column up to 1 + tau counts as occluding (the constant area), then
// fades linearly back to open over the column's own length (the falloff area); a sample whose
// surface lies in front of the constant area is "occluded" and flagged for the second phase of
// the stenciled variants (ssao/svao.h). Distances along the column are in units of r. No
// distance weight: the ball is VAO's falloff, whatever exao's falloff is.

#include <cstdint>
#include <vector>

#include "core/error.h"
#include "ssao/settings.h"
#include "ssao/view.h"

namespace exao::ssao {

struct VaoOptions {
  double thickness = 0.5;  // tau, [0, 1]: seed 001 sets it per scene in [0, 1]; the middle
};

[[nodiscard]] Result<void> check(const VaoOptions& options);

inline constexpr int kVaoSamples = 8;

/// One line sample of one pixel: where it reads the depth and how its column is cut.
struct VaoSample {
  bool valid = false;        // part of the column lies above the tangent plane
  std::int64_t pixel = -1;   // the pixel under the sample point, -1 off screen
  double z_lo = 0.0, z_hi = 0.0, height = 1.0;  // hemisphere part [z_lo, z_hi] of the column, full height h
  glm::dvec3 point{0.0};     // the sample point P + offset on the disc, the column's z = 0
};

/// Sample i (0 .. 7) of pixel p, a valid pixel of the view.
[[nodiscard]] VaoSample vao_sample(const View& view, const Settings& settings, std::size_t p, int i);

/// Unoccupied length of a sample's column when the surface along it is at z (units of r,
/// toward the eye, 0 at the receiver), after the halo model.
[[nodiscard]] double unoccupied(const VaoSample& sample, double z, double thickness);

/// z of a world point on the sample's column: (D - P) . e / r.
[[nodiscard]] double column_z(const View& view, const Settings& settings, std::size_t p, const glm::dvec3& point);

/// z where the sample's column meets the surface pixel q holds: the plane through q's point
/// with q's normal, extended from q's centre to the column (column_z of q's point when the
/// column runs along that plane). Reading q's centre instead would be up to 0.7 pixels off the
/// column, which on a surface seen at a grazing angle is a depth error larger than a small r:
/// an open floor seen at 20 degrees averaged 0.97 at r = 0.1, and the error set flags.
[[nodiscard]] double surface_z(const View& view, const Settings& settings, std::size_t p, const VaoSample& sample, std::size_t q);

struct VaoResult {
  // VAO (flagged samples after the halo model), before any blur and not clamped: on an open
  // surface seen at an angle a pixel's eight samples estimate the half ball's volume only on
  // average (values from about 0.75 to 1.25), and the estimator is unbiased (its mean over a
  // 4 x 4 block is 1), so a clamp before the blur would bias it dark: compare_view clamps after.
  // A pixel whose ball projects to less than a pixel is 1, like HBAO's.
  std::vector<float> ao;
  std::vector<float> unflagged;        // 2/8 sum over unflagged samples only: seed 001's phase 1
  std::vector<std::uint8_t> flags;     // bit i: sample i's surface lies in front of the constant area
  std::vector<std::uint8_t> stencil;   // the stochastic depth mask: pixels a flagged sample reads
};

[[nodiscard]] VaoResult vao(const View& view, const Settings& settings, const VaoOptions& options);

}  // namespace exao::ssao
