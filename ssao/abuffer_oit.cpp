#include "ssao/abuffer_oit.h"

#include <cassert>

#include <tbb/parallel_for.h>

namespace exao::ssao {

std::vector<float> abuffer_oit_ao(const View& view, const FragmentBuffer& fragments, const Scene& scene,
                                  const Settings& settings, const HbaoOptions& options) {
  assert(fragments.width == view.width && fragments.height == view.height);
  const detail::AllFragments policy{&fragments, &scene};
  std::vector<float> ao(view.pixel_count(), 1.0f);
  tbb::parallel_for(std::size_t{0}, view.pixel_count(), [&](std::size_t p) {
    if (!view.valid[p]) return;
    double blended = 0.0, transmittance = 1.0;
    const auto list = fragments.at(p);
    for (std::size_t k = 0; k < list.size() && transmittance > 0.0; ++k) {
      const Fragment& f = list[k];
      const double alpha = fragment_opacity(scene, view, p, f);
      if (!(alpha > 0.0)) continue;
      const auto v = scene.triangle(f.triangle);
      const glm::dvec3 n = glm::normalize(glm::cross(glm::dvec3(v[1]) - glm::dvec3(v[0]), glm::dvec3(v[2]) - glm::dvec3(v[0])));
      const bool gbuffer = k == 0 && f.triangle == view.triangle[p];
      const glm::dvec3 P = gbuffer ? glm::dvec3(view.position[p]) : view.point_at(p, static_cast<double>(f.depth));
      const double depth = gbuffer ? static_cast<double>(view.depth[p]) : static_cast<double>(f.depth);
      const bool front = glm::dot(n, view.eye - P) > 0.0;
      // Eq. 3: the exterior hemisphere's weight.
      const double w = front ? alpha : 1.0 - alpha;
      const auto walk = [&](const glm::dvec3& normal) {
        // The G-buffer's own normal (turned toward the eye) where it faces the same way.
        const glm::dvec3 m = gbuffer && glm::dot(glm::dvec3(view.normal[p]), normal) > 0.0 ? glm::dvec3(view.normal[p]) : normal;
        return detail::march_receiver(view, settings, options, policy, p, P, m, depth);
      };
      // Eq. 4; a weight of 0 needs no walk (opaque geometry walks once, toward the eye).
      double layer = 0.0;
      if (w > 0.0) layer += w * walk(n);
      if (w < 1.0) layer += (1.0 - w) * walk(-n);
      blended += transmittance * alpha * layer;
      transmittance *= 1.0 - alpha;
    }
    ao[p] = static_cast<float>(blended + transmittance);
  });
  return ao;
}

}  // namespace exao::ssao
