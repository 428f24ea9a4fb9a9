#include "core/ground_plane.h"

#include <algorithm>
#include <cmath>

namespace exao {

Result<float> add_ground_plane(Scene& scene, std::optional<float> height) {
  if (scene.ground_triangles > 0) return fail("ground: the scene has a ground plane already");
  const Bounds bounds = scene.bounds();
  if (bounds.empty()) return fail("ground: the scene has no triangles to stand on a plane");
  if (height && !std::isfinite(*height)) return fail("ground: the height must be finite");
  const float reach = 0.5f * std::max(bounds.extent().x, bounds.extent().z) + kGroundMargin * bounds.diagonal();
  float y = height.value_or(bounds.lo.y);
  if (!height) {
    // A receiver exactly at the plane's height (the bottom edge of a model standing on it) would
    // be exempt from it by the surface rule (core/surface_rule.h): the plane goes a few times the
    // rule's tolerance lower, so that the contact still gets its shadow.
    const double scale = std::max({std::abs(double(bounds.centre().x)) + reach, std::abs(double(bounds.centre().z)) + reach,
                                   std::abs(double(y))});
    y = static_cast<float>(double(y) - kGroundGapUlps * std::ldexp(scale, -24));
  }
  const glm::vec3 c(bounds.centre().x, y, bounds.centre().z);
  // Counter-clockwise seen from +Y: the front face looks up at the model.
  const glm::vec3 a = c + glm::vec3(-reach, 0.0f, -reach), b = c + glm::vec3(-reach, 0.0f, reach);
  const glm::vec3 d = c + glm::vec3(reach, 0.0f, reach), e = c + glm::vec3(reach, 0.0f, -reach);
  const std::size_t before = scene.triangle_count();
  scene.add_triangle(a, b, d, true, -1);
  scene.add_triangle(a, d, e, true, -1);
  // add_triangle counts what it reads; the plane is not part of what the file held.
  scene.report.triangles_read -= 2;
  scene.ground_triangles = scene.triangle_count() - before;
  if (scene.ground_triangles != 2) return fail("ground: the plane is degenerate (a model of zero size?)");
  return y;
}

}  // namespace exao
