#include "ssao/sd_hbao.h"

#include <cassert>

namespace exao::ssao {
namespace {

struct StochasticLayers {
  static constexpr bool kAllLayers = false;
  const StochasticDepth* map;
  template <class Emit>
  void layers(std::size_t q, Emit&& emit) const {
    for (const float w : map->at(q)) {
      if (w != kNoDepth) emit(static_cast<double>(w), 1.0);
    }
  }
};

}  // namespace

std::vector<float> sd_hbao(const View& view, const StochasticDepth& map, const Settings& settings,
                           const HbaoOptions& options) {
  assert(map.width == view.width && map.height == view.height);
  return detail::horizon_march(view, settings, options, StochasticLayers{&map});
}

}  // namespace exao::ssao
