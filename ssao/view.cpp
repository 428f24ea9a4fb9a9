#include "ssao/view.h"

#include <cmath>
#include <limits>

#include "raster/gbuffer.h"

namespace exao::ssao {

View view_basis(const Camera& camera, int width, int height) {
  View v;
  v.camera = camera;
  v.width = width;
  v.height = height;
  v.eye = glm::dvec3(camera.eye);
  v.forward = glm::dvec3(camera.forward);
  v.up = glm::dvec3(camera.up);
  v.right = glm::dvec3(glm::cross(camera.forward, camera.up));
  v.tan_half = std::tan(0.5 * static_cast<double>(camera.yfov));
  v.aspect = static_cast<double>(width) / static_cast<double>(height);
  return v;
}

View make_view(const Scene& scene, const Camera& camera, int width, int height) {
  View v = view_basis(camera, width, height);
  const raster::GBuffer g = raster::rasterize_gbuffer(scene, camera, width, height);
  v.receivers = raster::gbuffer_receivers(scene, camera, g);
  const std::size_t n = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  v.valid.assign(n, 0);
  v.position.assign(n, glm::vec3(0.0f));
  v.normal.assign(n, glm::vec3(0.0f, 0.0f, 1.0f));
  v.depth.assign(n, std::numeric_limits<float>::infinity());
  v.triangle = g.triangle;
  for (std::size_t i = 0; i < v.receivers.receivers.size(); ++i) {
    const std::uint32_t p = v.receivers.pixel[i];
    const Receiver& r = v.receivers.receivers[i];
    v.valid[p] = 1;
    v.position[p] = r.position;
    v.normal[p] = glm::normalize(r.normal);
    v.depth[p] = static_cast<float>(glm::dot(glm::dvec3(r.position) - v.eye, v.forward));
  }
  return v;
}

}  // namespace exao::ssao
