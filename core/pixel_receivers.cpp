#include "core/pixel_receivers.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace exao {

Receiver pixel_receiver(const Scene& scene, const Camera& camera, int width, int height, std::uint32_t pixel,
                        std::uint32_t triangle, float distance) {
  const int x = static_cast<int>(pixel % static_cast<std::uint32_t>(width));
  const int y = static_cast<int>(pixel / static_cast<std::uint32_t>(width));
  const glm::vec3 direction = pixel_ray(camera, width, height, x, y);
  const auto tri = scene.triangle(triangle);
  glm::vec3 normal = glm::normalize(glm::cross(tri[1] - tri[0], tri[2] - tri[0]));
  if (glm::dot(normal, direction) > 0.0f) normal = -normal;
  return Receiver{camera.eye + distance * direction, normal, pixel};
}

PixelReceivers pixel_receivers(const EmbreeScene& embree, const Scene& scene, const Camera& camera, int width,
                               int height) {
  const std::size_t pixels = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  std::vector<std::optional<EmbreeScene::Hit>> hits(pixels);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, pixels, 1024), [&](const tbb::blocked_range<std::size_t>& range) {
    for (std::size_t p = range.begin(); p < range.end(); ++p) {
      const int x = static_cast<int>(p % static_cast<std::size_t>(width));
      const int y = static_cast<int>(p / static_cast<std::size_t>(width));
      hits[p] = embree.closest_hit(camera.eye, pixel_ray(camera, width, height, x, y));
    }
  });
  PixelReceivers result;
  result.width = width;
  result.height = height;
  for (std::size_t p = 0; p < pixels; ++p) {
    if (!hits[p]) continue;
    const auto pixel = static_cast<std::uint32_t>(p);
    result.receivers.push_back(pixel_receiver(scene, camera, width, height, pixel, hits[p]->triangle, hits[p]->distance));
    result.pixel.push_back(pixel);
    result.triangle.push_back(hits[p]->triangle);
  }
  return result;
}

}  // namespace exao
