#pragma once
// exao::AoError: how far AO values are from reference values, one pair at a time. The one metric
// behind `exao bench` (against Embree, and a raster LOD against exact raster), `exao bake
// --compare` (core/agreement.h) and `exao compare` (ssao/error_stats.h).

#include <algorithm>
#include <cmath>
#include <cstddef>

#include "core/mask_set.h"

namespace exao {

struct AoError {
  std::size_t count = 0;       // pairs added
  double sum = 0.0;            // of AO - reference: > 0 lighter than the reference
  double sum_abs = 0.0;
  double sum_squares = 0.0;
  double max_abs = 0.0;
  std::size_t within_255 = 0;  // pairs with |AO - reference| <= 1/255 (a hair of slack, so that
  std::size_t within_16 = 0;   // values one 8-bit step apart, rounded through float, count); <= 1/16
  std::size_t same_8bit = 0;   // pairs equal after the rounding of io/image_io's PNG writer

  void add(double ao, double reference) {
    const double d = ao - reference;
    ++count;
    sum += d;
    sum_abs += std::abs(d);
    sum_squares += d * d;
    max_abs = std::max(max_abs, std::abs(d));
    within_255 += std::abs(d) <= 1.0 / 255.0 + 1e-7;
    within_16 += std::abs(d) <= 1.0 / 16.0 + 1e-7;
    same_8bit += png_level(ao) == png_level(reference);
  }
  AoError& operator+=(const AoError& o) {
    count += o.count;
    sum += o.sum;
    sum_abs += o.sum_abs;
    sum_squares += o.sum_squares;
    max_abs = std::max(max_abs, o.max_abs);
    within_255 += o.within_255;
    within_16 += o.within_16;
    same_8bit += o.same_8bit;
    return *this;
  }

  // Over the pairs added; with none, no error (0, and shares of 1 for the 8-bit one).
  [[nodiscard]] double mean_abs() const { return count ? sum_abs / double(count) : 0.0; }
  [[nodiscard]] double bias() const { return count ? sum / double(count) : 0.0; }
  [[nodiscard]] double rmse() const { return count ? std::sqrt(sum_squares / double(count)) : 0.0; }
  [[nodiscard]] double within_255_share() const { return count ? double(within_255) / double(count) : 0.0; }
  [[nodiscard]] double within_16_share() const { return count ? double(within_16) / double(count) : 0.0; }
  [[nodiscard]] double identical_8bit_share() const { return count ? double(same_8bit) / double(count) : 1.0; }

 private:
  [[nodiscard]] static long png_level(double ao) {
    return std::lround(std::clamp(static_cast<float>(ao), 0.0f, 1.0f) * 255.0f);
  }
};

/// How AO from `masks` differs from AO from `reference` (the same receivers, in order).
[[nodiscard]] inline AoError ao_error(const MaskSet& reference, const MaskSet& masks) {
  AoError e;
  for (std::size_t i = 0; i < reference.size(); ++i) e.add(masks.ao(i), reference.ao(i));
  return e;
}

}  // namespace exao
