#pragma once
// exao::ssao::error_stats: how far a method's AO is from the exact AO on the same pixels, as the
// one AO-error metric (core/ao_error.h).

#include <cstdint>
#include <span>

#include "core/ao_error.h"

namespace exao::ssao {

/// Over the pixels where valid is non-zero (AoError::count of them); all three spans the same size.
[[nodiscard]] AoError error_stats(std::span<const float> ao, std::span<const float> exact,
                                  std::span<const std::uint8_t> valid);

}  // namespace exao::ssao
