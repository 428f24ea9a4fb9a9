#include "ssao/abuffer_ao.h"

#include <cassert>

namespace exao::ssao {
namespace {

struct AllFragments {
  static constexpr bool kAllLayers = true;
  const FragmentBuffer* fragments;
  const Scene* scene;
  template <class Emit>
  void layers(std::size_t q, Emit&& emit) const {
    for (const Fragment& f : fragments->at(q)) {
      const float opacity = scene->opacity(f.triangle);
      if (opacity > 0.0f) emit(static_cast<double>(f.depth), static_cast<double>(opacity));
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
