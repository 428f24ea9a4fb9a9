#pragma once
// What every screen-space method shares with exao's exact AO: the radius and the falloff, and
// the per-pixel jitter that stands in for the papers' 4 x 4 noise textures.
//
// Matching exao's falloff (core/sample_pattern.h: rho(D) = 1, 1 - D/r or (1 - D/r)^2): every
// estimator that weighs an occluder by its distance (HBAO's and HBAO+'s attenuation W, the
// A-buffer's and the stochastic variants') uses W(D) = rho(D) and ignores occluders beyond r,
// in place of the papers' own W (Bavoil's 1 - D^2/r^2). VAO has no distance weight: its ball of
// radius r is its falloff, and it is the same whatever --falloff says.

#include <cmath>
#include <cstdint>

#include "core/random.h"
#include "core/sample_pattern.h"

namespace exao::ssao {

struct Settings {
  double radius = 1.0;                  // r, world units, > 0: the exact AO's radius
  Falloff falloff = Falloff::Constant;  // exao's rho
  int blur_radius = 4;                  // bilateral filter half-width in pixels, 0: none (ssao/bilateral.h)
};

/// rho(d) for 0 <= d < r, else 0.
[[nodiscard]] inline double falloff_weight(const Settings& s, double d) {
  if (!(d < s.radius)) return 0.0;
  const double x = 1.0 - d / s.radius;
  switch (s.falloff) {
    case Falloff::Constant: return 1.0;
    case Falloff::Linear: return x;
    case Falloff::Quadratic: return x * x;
  }
  return 1.0;
}

/// A number in [0, 1) that repeats every 4 x 4 pixels (stream k), like a tiled noise texture:
/// seeds 000 and 001 randomise directions per pixel of a 4 x 4 block and let the blur remove it.
/// Stratified: the 16 pixels of a block take the 16 values (b + 1/2) / 16, shifted (mod 1) by a
/// constant per stream, where b is the cell's entry of a 4 x 4 Bayer matrix for even streams and
/// that entry with its 4 bits reversed for odd ones. A method that needs two numbers per pixel
/// (HBAO's rotation, stream 0, and its step offset, stream 1) so gets a Hammersley set over the
/// block, (b / 16, reverse(b) / 16): each number alone takes all 16 strata, and the pairs are
/// jointly stratified, not the one number shifted (which would tie the first step's distance to
/// the direction). Bavoil et al.'s and NVIDIA's shaders read both from one random texture; seed
/// 000 leaves the noise open.
[[nodiscard]] inline double block_jitter(std::size_t pixel, int width, int k) {
  static constexpr int kBayer[16] = {0, 8, 2, 10, 12, 4, 14, 6, 3, 11, 1, 9, 15, 7, 13, 5};
  const std::size_t x = pixel % static_cast<std::size_t>(width), y = pixel / static_cast<std::size_t>(width);
  const std::size_t cell = (y & 3u) * 4u + (x & 3u);
  int b = kBayer[cell];
  if (k & 1) b = ((b & 1) << 3) | ((b & 2) << 1) | ((b & 4) >> 1) | ((b & 8) >> 3);
  const double shift = unit_double(mix64(static_cast<std::uint64_t>(k) + 1));
  const double v = (b + 0.5) / 16.0 + shift;
  return v - std::floor(v);
}

}  // namespace exao::ssao
