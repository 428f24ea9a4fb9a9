#pragma once
// exao::ssao::ErrorStats: how far a method's AO is from the exact AO on the same pixels.

#include <cstddef>
#include <cstdint>
#include <span>

namespace exao::ssao {

struct ErrorStats {
  std::size_t pixels = 0;      // pixels compared (those that see a triangle)
  double mean_abs = 0.0;       // mean |AO - exact|
  double bias = 0.0;           // mean AO - exact: > 0 lighter than exact (missed occlusion)
  double rmse = 0.0;
  double within_255 = 0.0;     // share of pixels with |AO - exact| <= 1/255
  double within_16 = 0.0;      // ... <= 1/16
};

/// Over the pixels where valid is non-zero; all three spans the same size.
[[nodiscard]] ErrorStats error_stats(std::span<const float> ao, std::span<const float> exact,
                                     std::span<const std::uint8_t> valid);

}  // namespace exao::ssao
