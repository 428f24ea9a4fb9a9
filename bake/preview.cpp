#include "bake/preview.h"

#include <algorithm>
#include <cmath>

#include <tbb/parallel_for.h>

#include "bake/document_impl.h"

namespace exao::bake {
namespace {

// Barycentric coordinates of p (on or near the triangle's plane), clamped into the triangle.
glm::dvec3 barycentric3(const std::array<glm::vec3, 3>& t, const glm::dvec3& p) {
  const glm::dvec3 a(t[0]), e1 = glm::dvec3(t[1]) - a, e2 = glm::dvec3(t[2]) - a, d = p - a;
  const double d00 = glm::dot(e1, e1), d01 = glm::dot(e1, e2), d11 = glm::dot(e2, e2);
  const double d20 = glm::dot(d, e1), d21 = glm::dot(d, e2);
  const double det = d00 * d11 - d01 * d01;
  if (!(std::abs(det) > 0.0)) return {1.0 / 3.0, 1.0 / 3.0, 1.0 / 3.0};
  const double v = (d11 * d20 - d01 * d21) / det;
  const double w = (d00 * d21 - d01 * d20) / det;
  glm::dvec3 b = glm::max(glm::dvec3(1.0 - v - w, v, w), glm::dvec3(0.0));
  return b / (b.x + b.y + b.z);
}

// Bilinear lookup with clamp-to-edge, as the map's sampler asks viewers to do.
float sample(const AoMap& map, glm::vec2 uv) {
  const double x = static_cast<double>(uv.x) * map.size - 0.5, y = static_cast<double>(uv.y) * map.size - 0.5;
  const double fx = std::floor(x), fy = std::floor(y);
  const auto at = [&](double px, double py) {
    const int ix = std::clamp(static_cast<int>(px), 0, map.size - 1);
    const int iy = std::clamp(static_cast<int>(py), 0, map.size - 1);
    return static_cast<double>(map.ao[static_cast<std::size_t>(iy) * static_cast<std::size_t>(map.size) + static_cast<std::size_t>(ix)]);
  };
  const double tx = x - fx, ty = y - fy;
  const double top = (1.0 - tx) * at(fx, fy) + tx * at(fx + 1.0, fy);
  const double bottom = (1.0 - tx) * at(fx, fy + 1.0) + tx * at(fx + 1.0, fy + 1.0);
  return static_cast<float>((1.0 - ty) * top + ty * bottom);
}

}  // namespace

AoImage render_preview(const Document& document, const BakeResult& result, const EmbreeScene& embree,
                       const Camera& camera, int width, int height) {
  const ModelWalk& walk = document.impl().walk;
  const Scene& scene = document.scene();
  AoImage image;
  image.width = width;
  image.height = height;
  const std::size_t n = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  image.ao.assign(n, 1.0f);
  image.coverage.assign(n, 0.0f);
  tbb::parallel_for(0, height, [&](int y) {
    for (int x = 0; x < width; ++x) {
      const glm::vec3 direction = pixel_ray(camera, width, height, x, y);
      const auto hit = embree.closest_hit(camera.eye, direction);
      if (!hit || hit->triangle >= walk.triangle_source.size()) continue;
      const TriangleSource& source = walk.triangle_source[hit->triangle];
      const auto corners = walk.corners(source.part, source.triangle);
      const glm::dvec3 p = glm::dvec3(camera.eye) + static_cast<double>(hit->distance) * glm::dvec3(direction);
      const glm::dvec3 b = barycentric3(scene.triangle(hit->triangle), p);
      float ao = 1.0f;
      if (result.target == Target::Vertex && source.part < result.part_vertex_ao.size()) {
        const std::vector<float>& values = result.part_vertex_ao[source.part];
        ao = static_cast<float>(b.x * values[corners[0]] + b.y * values[corners[1]] + b.z * values[corners[2]]);
      } else if (result.target == Target::Texture && source.part < result.part_corner_uv.size() &&
                 result.part_map[source.part] >= 0) {
        const glm::vec2* uv = result.part_corner_uv[source.part].data() + 3 * static_cast<std::size_t>(source.triangle);
        const glm::dvec2 t = b.x * glm::dvec2(uv[0]) + b.y * glm::dvec2(uv[1]) + b.z * glm::dvec2(uv[2]);
        ao = sample(result.maps[static_cast<std::size_t>(result.part_map[source.part])], glm::vec2(t));
      }
      const std::size_t i = static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x);
      image.ao[i] = ao;
      image.coverage[i] = 1.0f;
    }
  });
  return image;
}

}  // namespace exao::bake
