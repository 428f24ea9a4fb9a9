#include "ssao/hbao.h"

#include <string>

namespace exao::ssao {
namespace {

struct FirstLayerOnly {
  static constexpr bool kAllLayers = false;
  template <class Emit>
  void layers(const View&, std::size_t, const glm::dvec2&, Emit&&) const {}
};

}  // namespace

Result<void> check(const HbaoOptions& options) {
  if (options.directions < 1 || options.directions > 64) return fail("directions: must be from 1 to 64, got " + std::to_string(options.directions));
  if (options.steps < 1 || options.steps > 64) return fail("steps: must be from 1 to 64, got " + std::to_string(options.steps));
  if (!(options.bias >= 0.0 && options.bias < 1.0)) return fail("bias: must be in [0, 1), got " + std::to_string(options.bias));
  if (options.cosine && options.angles != Angles::Tangent) {
    return fail("cosine: cosine weighting needs angles from the tangent plane (--angles tangent)");
  }
  return {};
}

std::vector<float> hbao(const View& view, const Settings& settings, const HbaoOptions& options) {
  return detail::horizon_march(view, settings, options, FirstLayerOnly{});
}

}  // namespace exao::ssao
