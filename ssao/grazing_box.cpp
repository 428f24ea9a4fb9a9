#include "ssao/grazing_box.h"

namespace exao::ssao {
namespace {

// A quad a, b, c, d, counter-clockwise seen from its front, as two triangles.
void add_quad(Scene& scene, glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 d) {
  scene.add_triangle(a, b, c, false, 0);
  scene.add_triangle(a, c, d, false, 0);
}

}  // namespace

Scene make_grazing_box(bool box) {
  Scene scene;
  scene.name = kGrazingBoxName;
  add_quad(scene, {-6.0f, 0.0f, 6.0f}, {6.0f, 0.0f, 6.0f}, {6.0f, 0.0f, -6.0f}, {-6.0f, 0.0f, -6.0f});  // floor, +Y
  if (box) {
    const float x0 = -1.0f, x1 = 1.0f, y1 = 2.0f, z0 = -3.0f, z1 = 0.0f;
    add_quad(scene, {x0, 0.0f, z1}, {x1, 0.0f, z1}, {x1, y1, z1}, {x0, y1, z1});  // +Z, facing the camera
    add_quad(scene, {x1, 0.0f, z0}, {x0, 0.0f, z0}, {x0, y1, z0}, {x1, y1, z0});  // -Z
    add_quad(scene, {x1, 0.0f, z1}, {x1, 0.0f, z0}, {x1, y1, z0}, {x1, y1, z1});  // +X: the side seen edge-on
    add_quad(scene, {x0, 0.0f, z0}, {x0, 0.0f, z1}, {x0, y1, z1}, {x0, y1, z0});  // -X
    add_quad(scene, {x0, y1, z1}, {x1, y1, z1}, {x1, y1, z0}, {x0, y1, z0});      // top, +Y
  }
  scene.cameras.push_back(look_at({1.0f, 3.0f, 5.0f}, {1.0f, 0.0f, -2.0f}, 50.0f));
  scene.cameras.back().name = "edge-on";
  return scene;
}

}  // namespace exao::ssao
