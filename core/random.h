#pragma once
// Deterministic pseudo-random numbers: the same on every machine and compiler, unlike the
// distributions of <random>, so a seed or a receiver key always gives the same rays.

#include <cstdint>

namespace exao {

/// SplitMix64's finaliser: a strong 64-bit mix, used to hash receiver keys.
[[nodiscard]] constexpr std::uint64_t mix64(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

/// A float in [0, 1) from the top 24 bits of a 64-bit value (exactly representable).
[[nodiscard]] constexpr float unit_float(std::uint64_t bits) {
  return static_cast<float>(bits >> 40) * (1.0f / 16777216.0f);
}

/// A double in [0, 1) from the top 53 bits.
[[nodiscard]] constexpr double unit_double(std::uint64_t bits) {
  return static_cast<double>(bits >> 11) * (1.0 / 9007199254740992.0);
}

/// SplitMix64 stream.
class Rng {
 public:
  explicit constexpr Rng(std::uint64_t seed) : state_(seed) {}
  constexpr std::uint64_t next() {
    state_ += 0x9E3779B97F4A7C15ull;
    return mix64(state_);
  }
  constexpr double uniform() { return unit_double(next()); }
  /// An integer in [0, n), n > 0 (Lemire's multiply-shift; the bias is below 2^-32 for n < 2^32).
  constexpr std::uint32_t below(std::uint32_t n) {
    return static_cast<std::uint32_t>(((next() >> 32) * static_cast<std::uint64_t>(n)) >> 32);
  }

 private:
  std::uint64_t state_;
};

}  // namespace exao
