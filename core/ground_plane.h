#pragma once
// A ground plane under a model (exao bake --ground): the contact shadow a model standing on a
// floor gets, for models that come without one (a truck, a statue).

#include <optional>

#include "core/error.h"
#include "core/scene.h"

namespace exao {

/// How far the plane reaches beyond the model's footprint, in bounding-box diagonals.
inline constexpr float kGroundMargin = 2.0f;

/// How far below the model's lowest point the plane goes by default, in float ulps (2^-24) of its
/// largest coordinate: 4 x the surface rule's tolerance (core/surface_rule.h, kOnPlaneUlps), so
/// that receivers on the model's bottom edge do not start in the plane's plane.
inline constexpr double kGroundGapUlps = 64.0;

/// Appends two two-sided triangles to `scene`, at `height` along +Y (glTF's up axis), or just
/// below the model's lowest point (kGroundGapUlps) when `height` is empty. They form a square centred under the model,
/// reaching kGroundMargin diagonals beyond its footprint on every side, so that every ray of
/// a radius up to that length that leaves a receiver downwards meets it. Counted in
/// scene.ground_triangles, so bounds() (and with it every "% of the diagonal") still describes
/// the model. The plane is wound counter-clockwise seen from above, so that it also blocks as a
/// one-sided triangle (--sided one). Fails on an empty scene, a non-finite height, or a second
/// plane. Returns the height used.
[[nodiscard]] Result<float> add_ground_plane(Scene& scene, std::optional<float> height);

}  // namespace exao
