#include "ssao/abuffer_ao.h"

#include <cassert>

namespace exao::ssao {

std::vector<float> abuffer_ao(const View& view, const FragmentBuffer& fragments, const Scene& scene,
                              const Settings& settings, const HbaoOptions& options) {
  assert(fragments.width == view.width && fragments.height == view.height);
  return detail::horizon_march(view, settings, options, detail::AllFragments{&fragments, &scene});
}

}  // namespace exao::ssao
