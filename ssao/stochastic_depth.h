#pragma once
// exao::ssao::StochasticDepth: the stochastic depth map of seed 000 (Vermeer, Scandolo, Eisemann
// 2021, Sec. 3.1, Alg. 1): S depth samples per pixel, all at the pixel centre. Each fragment is
// stored in R = floor(alpha S + xi) of them (stratified, so a fragment is expected in alpha S
// samples), chosen as a random entry of the table of all S-bit masks with R bits set; each sample
// keeps the nearest fragment stored in it (the depth test). xi and the entry come from a hash of
// the pixel, the fragment's triangle and its depth, the paper's "pixel location, sample index and
// depth" seed. The map is drawn from the A-buffer, which holds every fragment the rasterizer
// would have shaded; a stencil restricts it to chosen pixels (seed 001's stenciled map).

#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "core/error.h"
#include "ssao/fragment_buffer.h"

namespace exao::ssao {

struct StochasticDepthOptions {
  int samples = 4;       // S, 1 .. 16: seed 000's Fig. 4 and seed 001 use 4
  double alpha = 0.2;    // global keep probability, (0, 1]: seed 000 uses 0.2 in all its tests
  std::uint64_t seed = 0;
};

/// "--sd-samples" / "--sd-alpha" style checks: S in 1..16, alpha in (0, 1].
[[nodiscard]] Result<void> check(const StochasticDepthOptions& options);

inline constexpr float kNoDepth = std::numeric_limits<float>::infinity();

struct StochasticDepth {
  int width = 0, height = 0, samples = 0;
  std::vector<float> depth;  // pixel * samples + j: view depth of sample j, kNoDepth when empty

  [[nodiscard]] std::span<const float> at(std::size_t pixel) const {
    return {depth.data() + pixel * static_cast<std::size_t>(samples), static_cast<std::size_t>(samples)};
  }
};

/// table[R]: every S-bit mask with exactly R bits set, in increasing order (R = 0 .. S).
[[nodiscard]] std::vector<std::vector<std::uint32_t>> subset_table(int samples);

/// The map drawn from `fragments`; with a non-empty `stencil` (one byte per pixel) only pixels
/// whose byte is non-zero get samples, the others stay empty. options must pass check().
[[nodiscard]] StochasticDepth make_stochastic_depth(const FragmentBuffer& fragments, const StochasticDepthOptions& options,
                                                    std::span<const std::uint8_t> stencil = {});

}  // namespace exao::ssao
