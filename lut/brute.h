#pragma once
// exao::lut::brute_occlusion: the `brute` backend (DESIGN.md section 5): for every receiver, the
// OR of triangle_mask over every triangle of the scene. The definition the accelerated backends
// must reproduce bit for bit (DESIGN.md section 8).

#include <cstdint>
#include <span>

#include "core/mask_set.h"
#include "core/progress.h"
#include "core/receiver_frame.h"
#include "lut/mask_engine.h"
#include "lut/triangle_set.h"

namespace exao::lut {

/// One receiver's brute mask: the OR of engine.triangle_mask over `candidates` (triangle indices,
/// any range of them), in their order, skipping the frame's excluded object and stopping once
/// every ray is blocked (more ORs change nothing). The one loop of brute_occlusion and of the
/// engine's single-point brute query.
template <int Bits, class Candidates>
[[nodiscard]] Mask<Bits> brute_mask(const MaskEngine& engine, const TriangleSet& triangles, const Frame& frame,
                                    const Candidates& candidates) {
  const Mask<Bits> all = engine.all_rays<Bits>();
  Mask<Bits> mask;
  for (const std::uint32_t t : candidates) {
    if (!triangles.blocks_for(t, frame)) continue;  // the excluded object
    mask |= engine.triangle_mask<Bits>(triangles, t, frame);
    if (mask == all) break;
  }
  return mask;
}

/// One mask per receiver, in the receivers' order: OR over all triangles t of
/// engine.triangle_mask(triangles, t, frame). A uniform grid over the triangles' influence
/// spheres (bounding sphere grown by r, and a little more for rounding) skips only triangles
/// that triangle_mask's influence-sphere test rejects, so the result is exactly the OR over all
/// triangles. Multithreaded with TBB; progress in receivers.
[[nodiscard]] MaskSet brute_occlusion(const MaskEngine& engine, const TriangleSet& triangles,
                                      std::span<const Receiver> receivers, const ProgressCallback& progress = {});

/// The same without the grid: literally every triangle for every receiver. For tests of the
/// grid on small inputs; O(receivers x triangles).
[[nodiscard]] MaskSet brute_occlusion_every_triangle(const MaskEngine& engine, const TriangleSet& triangles,
                                                     std::span<const Receiver> receivers);

}  // namespace exao::lut
