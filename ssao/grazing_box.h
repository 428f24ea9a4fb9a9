#pragma once
// exao::ssao::make_grazing_box: seed 000's Fig. 3 case as a scene `exao compare` knows by name
// ("grazing-box"): a 2 x 2 x 3 box (x in [-1, 1], y in [0, 2], z in [-3, 0]) on a 12 x 12 floor,
// seen by a camera ("edge-on") whose eye lies exactly in the plane x = 1 of the box's +X side,
// so that side projects to a line and leaves no fragment in any depth map of the main view,
// while it occludes the floor beside it (x just above 1). The box's top (y = 2) is farther than
// a radius of 1 from that floor, so at r = 1 only the side can occlude it: single-view screen
// space methods miss it, a secondary view to the right (seed 000's multi-view, Sec. 3.4) sees the
// side at an angle, and exact AO sees it all. Every coordinate is exact in float, and the eye and
// target share x = 1, so the camera's forward axis has no x part and the side is exactly edge-on.
// One-sided, fronts facing the open space. With box = false only the floor is left.

#include "core/scene.h"

namespace exao::ssao {

inline constexpr const char* kGrazingBoxName = "grazing-box";

[[nodiscard]] Scene make_grazing_box(bool box = true);

}  // namespace exao::ssao
