#pragma once
// Texel receivers for one AO map: the triangles of the meshes that share the
// map are rasterised conservatively in UV space; each texel they touch gets receivers at
// several sample points inside it, with position and normal interpolated from the triangle
// under the sample. The texel's AO is then the mean AO of its receivers.

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "bake/uv_raster.h"
#include "core/receiver_frame.h"

namespace exao::bake {

struct UvTriangle {
  UvTriangleCorners uv;                // texel units (uv * map size)
  std::array<glm::vec3, 3> position;   // world space
  std::array<glm::vec3, 3> normal;     // world space, unit; zero: use the face normal
  std::uint32_t source = 0;            // the caller's id of where it came from (overlap reports)
};

struct TexelReceivers {
  std::vector<Receiver> receivers;
  std::vector<std::uint32_t> texel;       // per receiver: y * width + x
  std::vector<std::uint8_t> covered;      // per texel: 1 when some triangle touches it
  std::size_t covered_texels = 0;
  /// Texels where a sample lies well inside two or more triangles (overlapping UVs, or one mesh
  /// drawn by several nodes): they get a receiver per triangle, so their AO is the average.
  std::size_t overlap_texels = 0;
  /// Up to a few (source, source) pairs seen overlapping, smaller id first (equal when a source
  /// overlaps itself, as mirrored halves sharing texels do), for the report.
  std::vector<std::array<std::uint32_t, 2>> overlap_examples;
};

/// Samples per texel are a k x k grid at ((i + 1/2) / k, (j + 1/2) / k) of the texel (k = 1: the
/// texel centre). A sample inside a triangle (barycentrics >= -1e-9, so shared edges lose no
/// sample) becomes a receiver of the triangle it lies deepest in. A texel whose samples all miss
/// (only partly covered) gets one receiver at the point of its triangles closest to its centre.
/// Receivers whose interpolated and face normals are both zero (degenerate in 3D) are dropped.
/// Keys run from first_key upwards, one per receiver, in texel order.
[[nodiscard]] TexelReceivers texel_receivers(std::span<const UvTriangle> triangles, int width, int height,
                                             int samples_per_side, std::uint64_t first_key);

}  // namespace exao::bake
