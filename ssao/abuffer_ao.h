#pragma once
// exao::ssao::abuffer_ao: A-buffer AO (Bauer, Knuth, Kuijper, Bender 2013; seed 004) in its
// horizon-based form (their Sec. V-B: HBAO over the fragment lists). Receivers are the first
// layer; at every step all fragments of the sampled pixel are examined and the one that would
// occlude most is kept (their Alg. 1, max over the list), its gain weighted by its material's
// opacity (their Eq. 1, alpha_omega: glTF BLEND alpha, MASK by its cutoff; core/scene.h). A
// semi-transparent occluder still raises the horizon: HBAO has one horizon per direction, so a
// later occluder behind it gains only above it, and is under-weighted against Eq. 1 (keeping
// Eq. 1 exactly would need every sample's angle and opacity per direction, and the slice's
// occlusion as the integral over elevations of 1 - prod(1 - alpha W) of the samples above).
// With opacities 0 and 1 only (glTF MASK cut-outs) this is exact: a fragment below its cutoff is
// skipped and one above it is opaque. Receivers are treated as opaque (their opaque mode: "the
// shadowing factor is only computed for the first layer"). Each fragment's sample is its
// triangle's plane met by the ray through the step's screen point (ssao/horizon_march.h).

#include <vector>

#include "core/scene.h"
#include "ssao/fragment_buffer.h"
#include "ssao/fragment_opacity.h"
#include "ssao/horizon_march.h"

namespace exao::ssao {
namespace detail {

/// The Layers policy of ssao/horizon_march.h over an A-buffer: every fragment of the sampled
/// pixel with its opacity (fragment_opacity; transparent ones skipped), each as its triangle's
/// plane met by the ray through the step's screen point.
struct AllFragments {
  static constexpr bool kAllLayers = true;
  const FragmentBuffer* fragments;
  const Scene* scene;
  template <class Emit>
  void layers(const View& view, std::size_t q, const glm::dvec2& c, Emit&& emit) const {
    for (const Fragment& f : fragments->at(q)) {
      const float opacity = fragment_opacity(*scene, view, q, f);
      if (!(opacity > 0.0f)) continue;
      // The fragment's triangle's plane, extended to the sample point c (ssao/horizon_march.h).
      const auto v = scene->triangle(f.triangle);
      const glm::dvec3 normal = glm::cross(glm::dvec3(v[1]) - glm::dvec3(v[0]), glm::dvec3(v[2]) - glm::dvec3(v[0]));
      emit(view.point_on_plane(c, view.point_at(q, static_cast<double>(f.depth)), normal), static_cast<double>(opacity));
    }
  }
};

}  // namespace detail

/// AO per pixel, before any blur. `fragments` must be the view's size and from `scene`.
[[nodiscard]] std::vector<float> abuffer_ao(const View& view, const FragmentBuffer& fragments, const Scene& scene,
                                            const Settings& settings, const HbaoOptions& options);

}  // namespace exao::ssao
