#pragma once
// A pinhole camera and the primary ray through a pixel centre.

#include <cstdint>
#include <optional>
#include <string>

#include <glm/glm.hpp>

#include "core/bounds.h"

namespace exao {

struct Camera {
  std::string name;
  glm::vec3 eye{0.0f};
  glm::vec3 forward{0.0f, 0.0f, -1.0f};  // unit
  glm::vec3 up{0.0f, 1.0f, 0.0f};        // unit, orthogonal to forward
  float yfov = 0.8f;                     // vertical field of view, radians, in (0, pi)
  std::optional<float> aspect;           // width / height, when the file fixes it
};

/// A camera at `eye` looking at `target` with vertical field of view `yfov_degrees`.
/// World up is +Y (glTF); when the view is vertical, +Z is used instead.
[[nodiscard]] Camera look_at(const glm::vec3& eye, const glm::vec3& target, float yfov_degrees);

/// A view that frames the whole box: looking at its centre from above and to the front
/// (+X, +Y, +Z octant), far enough that the bounding sphere fits the narrower field of view.
[[nodiscard]] Camera frame_bounds(const Bounds& bounds, float aspect);

/// "" when Embree may be given rays from this camera, else why not: the eye must be within
/// +-kMaxCoordinate (core/coordinate_limit.h), forward and up finite unit vectors, yfov in
/// (0, pi). Embree (as Debian builds it) aborts the program on a ray it finds invalid.
[[nodiscard]] std::string camera_problem(const Camera& camera);

/// Unit direction of the ray through the centre of pixel (x, y) of a width x height image;
/// y = 0 is the top row. The camera's aspect is ignored: pixels are square.
[[nodiscard]] glm::vec3 pixel_ray(const Camera& camera, int width, int height, int x, int y);

}  // namespace exao
