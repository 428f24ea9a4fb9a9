#pragma once
// exao::raster::InfluenceVolume: for one triangle, a shape whose far side, rasterised, covers the
// pixel of every receiver the triangle may occlude (paper Sec. 4.1), and the data of the five
// fragment culling tests (paper Sec. 4.2, raster/fragment_tests.h).
//
// Which receivers must be covered. triangle_mask (lut/mask_engine.h) is empty unless the ray
// origin p' = p + eps n of the receiver is within r of the triangle (its step 5), within R + r of
// the triangle's bounding-sphere centre (step 4) and, for a one-sided triangle, in front of it
// (step 2), all up to float rounding, which the slack G below bounds. The receiver point p on the
// pixel ray is within eps of p'. So every volume holds the set of points within
//     grow = r + eps + 4 G
// of the triangle (inside the sphere (centre, R + grow)), which leaves a margin of at least 3 G
// around every receiver that needs it; the margin absorbs the rounding of the volume's vertices,
// their projection and 1/4096-pixel snapping (about 1e-6 of the view depth), so the pixel centre
// of every such receiver is strictly inside the volume's projection and is rasterised.
//
// Shapes (R = radius of the triangle's bounding sphere):
//  - Prism (R / r > alpha): the hexagonal prism of the paper's Fig. 2, built from support planes
//    (each face is a plane max_v dot(m, v) + grow for a unit direction m, so the prism holds the
//    triangle's grow-neighbourhood whatever rounding the directions carry). The hexagon's corner
//    vertices are v + grow (n_edge + u) / (1 + n_edge . u), u the bisector of the two edge
//    normals at v: well conditioned for every triangle that is not degenerate. The top is at
//    grow above the plane; the base at grow below for a two-sided triangle, just below the
//    plane for a one-sided one (eps, the facing test's rounding and the margin).
//  - Billboard (R / r <= alpha): the paper's Fig. 3. The cone from the eye tangent to the
//    sphere S = (centre, R + grow) meets the plane of its tangent circle in that circle; a
//    regular 12-gon circumscribing it there projects onto a polygon holding S's projection. A
//    one-sided triangle's influence is S cut by the half-space in front of the base plane: the
//    12-gon is clipped by that half-space (in 3D, in the tangent circle's plane: on screen that is
//    the paper's separating line through the two points where the silhouette circle and the
//    ellipse meet) and a second 12-gon circumscribes the disc where the base plane cuts S (the
//    ellipse). The second polygon skips the pixels of the first, so no pixel is drawn twice. Both
//    sit at view depth centre + (R + grow), just behind S. Used only when the eye is well outside
//    S and S is wholly in front of the near plane.
//  - Box: the cube around S, for degenerate (needle, zero area) triangles when no billboard fits.
// Every shape is convex; its far faces are those whose plane has the eye on the inner side, so
// with the eye inside the volume every face is a far face, and homogeneous clipping of the faces
// (raster/screen_polygon.h) keeps exactly their parts in front of the near plane. A far face's
// fragment passes the inverted depth test when the receiver is on the inner side of the face's
// plane: along the pixel ray that is "the far surface is at or behind the receiver".

#include <array>
#include <cstdint>

#include <glm/glm.hpp>

#include "core/shadow_rays.h"
#include "lut/triangle_set.h"
#include "raster/projection.h"

namespace exao::raster {

enum class VolumeShape : std::uint8_t { Prism, Billboard, Box };

/// The run's constants for volumes and fragment tests, world units.
struct VolumeParams {
  float radius = 1.0f;  // r
  float offset = 0.0f;  // eps, the rays' origin offset
  float slack = 0.0f;   // G = 2e-5 * (scene scale + r): bounds the float rounding of every world-space
                        // test here and of triangle_mask's own tests (a few 1e-7 of the coordinates)
  float grow = 1.0f;    // r + eps + 4 G
  float alpha = 0.2f;   // R / r above which a prism is built
  double near = 0.0;    // the projection's near plane
};

/// `scene_scale`: raster::scene_scale of the scene and eye; `alpha` > 0.
[[nodiscard]] VolumeParams make_volume_params(const ShadowRays& rays, double scene_scale, float alpha, double near);

/// A half-space relative to the eye: x is inside when dot(m, x - eye) <= h.
struct DepthPlane {
  glm::vec3 m{0.0f};
  float h = 0.0f;
};

/// What the five fragment tests need of a triangle (raster/fragment_tests.h).
struct TriangleCull {
  glm::vec3 v0{0.0f}, v1{0.0f}, v2{0.0f};  // the triangle set's vertices
  glm::vec3 centre{0.0f};                 // bounding-sphere centre
  float sphere_reach2 = 0.0f;             // (R + r + G)^2
  glm::vec3 normal{0.0f};                 // unit normal of the counter-clockwise face (0 if degenerate)
  float plane_slack = 0.0f;               // bound on the plane-distance error (infinite if degenerate)
  float plane_reach = 0.0f;               // r + plane_slack
  float near_depth = 0.0f;                // smallest view depth of the triangle's vertices
  float depth_reach = 0.0f;               // r + G
  float slack = 0.0f;                     // G
  bool one_sided = false;
};

struct InfluenceVolume {
  static constexpr int kMaxVertices = 26;
  static constexpr int kMaxFaces = 8;
  static constexpr int kMaxIndices = 48;

  struct Face {
    std::uint8_t first = 0, count = 0;  // into index
    DepthPlane depth;                   // the far face's inverted depth test
  };

  VolumeShape shape = VolumeShape::Prism;
  int vertex_count = 0;
  std::array<ClipVertex, kMaxVertices> clip;  // the shape's vertices in clip space
  int face_count = 0;                          // far faces only
  std::array<Face, kMaxFaces> face;
  std::array<std::uint8_t, kMaxIndices> index;
  bool exclude_first = false;  // billboard of a one-sided triangle: face 1 skips face 0's pixels
  double max_depth = 0.0;      // largest view depth of the shape: no receiver deeper is inside
  TriangleCull cull;
};

/// Builds the volume of triangle t. False when no receiver can be occluded by it (a one-sided
/// triangle whose influence sphere is wholly behind its base plane).
[[nodiscard]] bool build_volume(const lut::TriangleSet& triangles, std::uint32_t t, const VolumeParams& params,
                                const Projection& projection, InfluenceVolume& volume);

}  // namespace exao::raster
