#include "core/camera.h"

#include <algorithm>
#include <cmath>

#include <glm/gtc/constants.hpp>

#include "core/coordinate_limit.h"

namespace exao {

Camera look_at(const glm::vec3& eye, const glm::vec3& target, float yfov_degrees) {
  Camera camera;
  camera.name = "look-at";
  camera.eye = eye;
  camera.forward = glm::normalize(target - eye);
  glm::vec3 world_up{0.0f, 1.0f, 0.0f};
  if (std::abs(glm::dot(world_up, camera.forward)) > 0.999f) world_up = {0.0f, 0.0f, 1.0f};
  const glm::vec3 right = glm::normalize(glm::cross(camera.forward, world_up));
  camera.up = glm::cross(right, camera.forward);
  camera.yfov = glm::radians(yfov_degrees);
  return camera;
}

Camera frame_bounds(const Bounds& bounds, float aspect) {
  const float yfov_degrees = 45.0f;
  const glm::vec3 centre = bounds.centre();
  const float radius = std::max(0.5f * bounds.diagonal(), 1e-6f);
  const float half_y = 0.5f * glm::radians(yfov_degrees);
  const float half_x = std::atan(std::tan(half_y) * aspect);
  const float distance = radius / std::sin(std::min(half_x, half_y));
  const glm::vec3 direction = glm::normalize(glm::vec3(0.6f, 0.5f, 0.8f));
  Camera camera = look_at(centre + distance * direction, centre, yfov_degrees);
  camera.name = "auto";
  return camera;
}

std::string camera_problem(const Camera& camera) {
  const glm::vec3& e = camera.eye;
  if (!(std::isfinite(e.x) && std::isfinite(e.y) && std::isfinite(e.z))) return "the eye is not a finite point";
  if (!within_coordinate_limit(e)) return "the eye is beyond +-1e17 (exao's coordinate limit)";
  const auto unit = [](const glm::vec3& v) {
    const float length = glm::length(v);
    return std::isfinite(length) && std::abs(length - 1.0f) < 1e-3f;
  };
  if (!unit(camera.forward) || !unit(camera.up)) return "the view direction is not finite (eye and target too far apart or too close)";
  if (!(camera.yfov > 0.0f && camera.yfov < glm::pi<float>())) return "the field of view is not between 0 and 180 degrees";
  return {};
}

glm::vec3 pixel_ray(const Camera& camera, int width, int height, int x, int y) {
  const float tan_half = std::tan(0.5f * camera.yfov);
  const float aspect = static_cast<float>(width) / static_cast<float>(height);
  const float sx = (2.0f * (static_cast<float>(x) + 0.5f) / static_cast<float>(width) - 1.0f) * tan_half * aspect;
  const float sy = (1.0f - 2.0f * (static_cast<float>(y) + 0.5f) / static_cast<float>(height)) * tan_half;
  const glm::vec3 right = glm::cross(camera.forward, camera.up);
  return glm::normalize(camera.forward + sx * right + sy * camera.up);
}

}  // namespace exao
