#include "ssao/sd_hbao.h"

#include <cassert>

namespace exao::ssao {
namespace {

struct StochasticLayers {
  static constexpr bool kAllLayers = false;
  const StochasticDepth* map;
  template <class Emit>
  void layers(const View& view, std::size_t q, const glm::dvec2&, Emit&& emit) const {
    // Depths only, no plane: at q's centre (ssao/horizon_march.h).
    for (const float w : map->at(q)) {
      if (w != kNoDepth) emit(view.point_at(q, static_cast<double>(w)), 1.0);
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
