#pragma once
// A picture of a bake: the baked AO seen from a camera, the way a viewer would show it. Each
// pixel's primary ray finds the visible triangle (Embree), and the AO there is interpolated from
// the baked vertex values or sampled bilinearly from the baked map, not computed again.

#include "bake/bake.h"
#include "bake/document.h"
#include "core/camera.h"
#include "core/embree_reference.h"
#include "io/image_io.h"

namespace exao::bake {

/// `embree` must be built from document.scene() (its triangle indices are the scene's).
/// Pixels that see nothing have coverage 0 (and AO 1). Multithreaded with TBB.
[[nodiscard]] AoImage render_preview(const Document& document, const BakeResult& result, const EmbreeScene& embree,
                                     const Camera& camera, int width, int height);

}  // namespace exao::bake
