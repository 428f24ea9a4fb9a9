#include "bake/options.h"

#include <cmath>
#include <string>

namespace exao::bake {

Result<void> check_options(const BakeOptions& o) {
  if (o.target == Target::Vertex) return {};
  if (o.texture_size < 16 || o.texture_size > 16384) {
    return fail("texture_size: the map size must be from 16 to 16384 texels, got " + std::to_string(o.texture_size));
  }
  const int k = static_cast<int>(std::lround(std::sqrt(static_cast<double>(o.texel_samples))));
  if (o.texel_samples < 1 || o.texel_samples > 256 || k * k != o.texel_samples) {
    return fail("texel_samples: must be a square number from 1 to 256 (1, 4, 9, 16...), got " +
                std::to_string(o.texel_samples));
  }
  if (o.margin < 0 || o.margin > 64) return fail("margin: must be from 0 to 64 texels, got " + std::to_string(o.margin));
  if (o.uv_set < 0 || o.uv_set > 15) return fail("uv_set: must be from 0 to 15, got " + std::to_string(o.uv_set));
  return {};
}

}  // namespace exao::bake
