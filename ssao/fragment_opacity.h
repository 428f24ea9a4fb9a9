#pragma once
// exao::ssao::fragment_opacity: the one place the screen-space methods ask how opaque an
// A-buffer fragment is (seed 004's alpha: Eq. 1's alpha_omega for occluders, Eq. 2-4's alpha_p
// for receivers, Eq. 5's a[i]_alpha for list compression). Today it is the material's
// (Scene::opacity: glTF BLEND's baseColorFactor alpha, MASK by its cutoff). A source that
// varies over a triangle (a base colour texture's alpha) plugs in here: the pixel and the
// fragment's depth give the point, view.point_at(pixel, depth), where it is sampled.

#include <cstddef>

#include "core/scene.h"
#include "ssao/fragment_buffer.h"
#include "ssao/view.h"

namespace exao::ssao {

/// Opacity in [0, 1] of fragment `f` of pixel `pixel` of `view` (1: opaque, 0: not there).
[[nodiscard]] inline float fragment_opacity(const Scene& scene, const View& view, std::size_t pixel, const Fragment& f) {
  (void)view;
  (void)pixel;
  return scene.opacity(f.triangle);
}

}  // namespace exao::ssao
