#include "ssao/abuffer_ao.h"

#include <cassert>

#include "core/cutouts.h"

namespace exao::ssao {
namespace {

struct AllFragments {
  static constexpr bool kAllLayers = true;
  const FragmentBuffer* fragments;
  const Scene* scene;
  template <class Emit>
  void layers(const View& view, std::size_t q, const glm::dvec2& c, Emit&& emit) const {
    for (const Fragment& f : fragments->at(q)) {
      // A cut-out's opacity is its alpha where the pixel's centre ray meets it (core/cutouts.h).
      const glm::dvec3 at = view.point_at(q, static_cast<double>(f.depth));
      const float opacity = scene->cutouts && scene->cutouts->tests(f.triangle)
                                ? scene->cutouts->opacity(f.triangle, glm::vec3(view.eye), glm::vec3(at - view.eye))
                                : scene->opacity(f.triangle);
      if (!(opacity > 0.0f)) continue;
      // The fragment's triangle's plane, extended to the sample point c (ssao/horizon_march.h).
      const auto v = scene->triangle(f.triangle);
      const glm::dvec3 normal = glm::cross(glm::dvec3(v[1]) - glm::dvec3(v[0]), glm::dvec3(v[2]) - glm::dvec3(v[0]));
      emit(view.point_on_plane(c, view.point_at(q, static_cast<double>(f.depth)), normal), static_cast<double>(opacity));
    }
  }
};

}  // namespace

std::vector<float> abuffer_ao(const View& view, const FragmentBuffer& fragments, const Scene& scene,
                              const Settings& settings, const HbaoOptions& options) {
  assert(fragments.width == view.width && fragments.height == view.height);
  return detail::horizon_march(view, settings, options, AllFragments{&fragments, &scene});
}

}  // namespace exao::ssao
