#include "ssao/error_stats.h"

#include <cassert>
#include <cmath>

namespace exao::ssao {

ErrorStats error_stats(std::span<const float> ao, std::span<const float> exact, std::span<const std::uint8_t> valid) {
  assert(ao.size() == exact.size() && ao.size() == valid.size());
  ErrorStats s;
  double sum_abs = 0.0, sum = 0.0, sum_sq = 0.0;
  std::size_t in255 = 0, in16 = 0;
  for (std::size_t p = 0; p < ao.size(); ++p) {
    if (!valid[p]) continue;
    const double d = static_cast<double>(ao[p]) - static_cast<double>(exact[p]);
    ++s.pixels;
    sum_abs += std::abs(d);
    sum += d;
    sum_sq += d * d;
    // A hair of slack so that values one 8-bit step apart, rounded through float, still count.
    in255 += std::abs(d) <= 1.0 / 255.0 + 1e-7;
    in16 += std::abs(d) <= 1.0 / 16.0 + 1e-7;
  }
  if (s.pixels == 0) return s;
  const double n = static_cast<double>(s.pixels);
  s.mean_abs = sum_abs / n;
  s.bias = sum / n;
  s.rmse = std::sqrt(sum_sq / n);
  s.within_255 = static_cast<double>(in255) / n;
  s.within_16 = static_cast<double>(in16) / n;
  return s;
}

}  // namespace exao::ssao
