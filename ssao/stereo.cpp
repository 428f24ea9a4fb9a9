#include "ssao/stereo.h"

#include <cmath>

#include "core/ao_error.h"

namespace exao::ssao {

std::pair<Camera, Camera> stereo_cameras(const Camera& camera, double ipd) {
  const glm::vec3 right = glm::normalize(glm::cross(camera.forward, camera.up));
  Camera left_eye = camera, right_eye = camera;
  left_eye.eye = camera.eye - static_cast<float>(0.5 * ipd) * right;
  right_eye.eye = camera.eye + static_cast<float>(0.5 * ipd) * right;
  left_eye.name = camera.name + "-left";
  right_eye.name = camera.name + "-right";
  return {left_eye, right_eye};
}

Correspondence correspond(const View& left, const View& right) {
  Correspondence c;
  const double cos_limit = std::cos(6.0 * 3.14159265358979323846 / 180.0);
  for (std::size_t p = 0; p < left.pixel_count(); ++p) {
    if (!left.valid[p]) continue;
    ++c.left_visible;
    const glm::dvec3 P(left.position[p]);
    const glm::dvec2 at = right.project(P);
    const std::int64_t nearest = right.pixel_at(at);
    if (nearest < 0 || !right.valid[static_cast<std::size_t>(nearest)]) continue;
    // Back-check: the right pixel's own point, seen from the left, must land on p.
    const glm::dvec2 back = left.project(glm::dvec3(right.position[static_cast<std::size_t>(nearest)]));
    const glm::dvec2 centre = left.centre(p);
    if (glm::length(back - centre) > 1.0) continue;
    const double x = at.x - 0.5, y = at.y - 0.5;
    const double x0 = std::floor(x), y0 = std::floor(y);
    if (x0 < 0 || y0 < 0 || x0 + 1 >= right.width || y0 + 1 >= right.height) continue;
    const double fx = x - x0, fy = y - y0;
    std::array<std::uint32_t, 4> q{};
    bool ok = true;
    for (int k = 0; k < 4; ++k) {
      const auto qx = static_cast<std::size_t>(x0) + static_cast<std::size_t>(k & 1);
      const auto qy = static_cast<std::size_t>(y0) + static_cast<std::size_t>(k >> 1);
      const std::size_t qi = qy * static_cast<std::size_t>(right.width) + qx;
      q[static_cast<std::size_t>(k)] = static_cast<std::uint32_t>(qi);
      ok = ok && right.valid[qi] && glm::dot(glm::dvec3(right.normal[qi]), glm::dvec3(left.normal[p])) >= cos_limit;
    }
    if (!ok) continue;
    c.left.push_back(static_cast<std::uint32_t>(p));
    c.right.push_back(q);
    c.weight.push_back({static_cast<float>((1 - fx) * (1 - fy)), static_cast<float>(fx * (1 - fy)),
                        static_cast<float>((1 - fx) * fy), static_cast<float>(fx * fy)});
  }
  return c;
}

Inconsistency inconsistency(const Correspondence& c, std::span<const float> left_ao, std::span<const float> right_ao) {
  Inconsistency r;
  r.pixels = c.left.size();
  r.share = c.left_visible ? static_cast<double>(r.pixels) / static_cast<double>(c.left_visible) : 0.0;
  // E(p) as the one AO-error metric (core/ao_error.h): its mean |d|, RMSE and 1/255 share.
  AoError e;
  for (std::size_t k = 0; k < c.left.size(); ++k) {
    double interpolated = 0.0;
    for (std::size_t j = 0; j < 4; ++j) interpolated += static_cast<double>(c.weight[k][j]) * right_ao[c.right[k][j]];
    e.add(left_ao[c.left[k]], interpolated);
  }
  r.mean = e.mean_abs();
  r.rmse = e.rmse();
  r.within_255 = e.within_255_share();
  return r;
}

}  // namespace exao::ssao
