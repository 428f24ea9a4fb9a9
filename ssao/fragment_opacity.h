#pragma once
// exao::ssao::fragment_opacity: the one place the screen-space methods ask how opaque an
// A-buffer fragment is (seed 004's alpha: Eq. 1's alpha_omega for occluders, Eq. 2-4's alpha_p
// for receivers, Eq. 5's a[i]_alpha for list compression): the material's (Scene::opacity:
// glTF BLEND's baseColorFactor alpha), or for a cut-out triangle its alpha where the pixel's
// centre ray meets it, from the same texture lookup as the exact methods (core/cutouts.h).

#include <cstddef>

#include "core/cutouts.h"
#include "core/scene.h"
#include "ssao/fragment_buffer.h"
#include "ssao/view.h"

namespace exao::ssao {

/// Opacity in [0, 1] of fragment `f` of pixel `pixel` of `view` (1: opaque, 0: not there).
[[nodiscard]] inline float fragment_opacity(const Scene& scene, const View& view, std::size_t pixel, const Fragment& f) {
  if (scene.cutouts && scene.cutouts->tests(f.triangle)) {
    const glm::dvec3 at = view.point_at(pixel, static_cast<double>(f.depth));
    return scene.cutouts->opacity(f.triangle, glm::vec3(view.eye), glm::vec3(at - view.eye));
  }
  return scene.opacity(f.triangle);
}

}  // namespace exao::ssao
