#pragma once
// The shared shadow-ray sample pattern (DESIGN.md section 2, paper Sec. 6): N cosine-weighted,
// well-stratified directions, each with a length drawn from the falloff.

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "core/enum_names.h"
#include "core/error.h"

namespace exao {

/// How occlusion fades with the distance D to the occluder, as the falloff rho(D) of Eq. 1:
/// constant: rho = 1 for D < r;  linear: rho = 1 - D/r;  quadratic: rho = (1 - D/r)^2.
enum class Falloff { Constant, Linear, Quadratic };

[[nodiscard]] constexpr auto enum_names(Falloff) {
  return std::to_array<EnumName<Falloff>>(
      {{Falloff::Constant, "constant"}, {Falloff::Linear, "linear"}, {Falloff::Quadratic, "quadratic"}});
}

[[nodiscard]] const char* falloff_name(Falloff falloff);
[[nodiscard]] Result<Falloff> parse_falloff(const std::string& name);

struct SamplePattern {
  int count = 0;                       // N: a multiple of 32 in [32, 1024]
  Falloff falloff = Falloff::Constant;
  std::uint64_t seed = 0;
  std::vector<glm::vec3> directions;   // unit, z > 0 (the frame's normal is +Z)
  std::vector<float> lengths;          // ray length / r, in (0, 1]
  std::vector<glm::vec3> points;       // directions[i] * lengths[i]: the sample points, r = 1
  float min_elevation = 0.0f;          // smallest asin(direction.z), radians, > 0

  /// Words of 64 bits that hold N bits.
  [[nodiscard]] int words() const { return (count + 63) / 64; }
};

inline constexpr std::uint64_t kDefaultPatternSeed = 0x65CA0;
inline constexpr int kMinSamples = 32;
inline constexpr int kMaxSamples = 1024;
/// Samples per cluster: make_sample_pattern orders the samples so that each run of
/// kSampleCluster consecutive ones is a compact cone of directions (N is a multiple of it).
inline constexpr int kSampleCluster = 16;

/// Checks that N is a multiple of 32 in [32, 1024]; the error names the value.
[[nodiscard]] Result<void> check_sample_count(int count);

/// Builds the pattern: N random points on the unit disc, Lloyd-relaxed, each moved to a random
/// point of its Voronoi cell, relaxed a little more, radii re-spaced to stratified levels of r^2
/// (so the horizon is sampled as densely as the rest), and lifted to the hemisphere
/// (z = sqrt(1 - x^2 - y^2)), which makes the directions cosine-weighted, and ordered so that
/// every kSampleCluster consecutive directions form a compact cone. Lengths come from the
/// falloff's inverse CDF at stratified, randomly permuted levels, so that the expected value of
/// Eq. 3 equals Eq. 2. Deterministic for (count, falloff, seed); single-threaded, well under a
/// second at N = 1024, and cached for the life of the process (thread-safe).
[[nodiscard]] Result<SamplePattern> make_sample_pattern(int count, Falloff falloff,
                                                        std::uint64_t seed = kDefaultPatternSeed);

/// The same without the process-wide cache that make_sample_pattern keeps; `count` must pass
/// check_sample_count. For tests of determinism.
[[nodiscard]] SamplePattern build_sample_pattern(int count, Falloff falloff, std::uint64_t seed);

/// A pattern of the caller's own directions (the public API's QuerySettings::directions)
/// instead of the generated one: N = directions.size() (check_sample_count), each direction
/// finite and non-zero, normalised here, with z > 0 after normalising (above the receiver's
/// tangent plane; the frame's tilt stays below the smallest elevation, as for the generated
/// pattern); lengths empty (all 1) or N values in (0, 1]. The order is the caller's: bit i is
/// direction i. The masks are exact in any order; they are fastest when every run of
/// kSampleCluster consecutive directions is a compact cone (lut/sample_clusters.h), as
/// make_sample_pattern orders its own. Errors name "directions" or "lengths" and the index.
[[nodiscard]] Result<SamplePattern> make_given_pattern(std::span<const glm::vec3> directions,
                                                       std::span<const float> lengths);

/// Saves as text: a header line, then one "x y z length" line per sample with enough digits that
/// loading gives back the same floats. Written to a temporary file, then renamed.
[[nodiscard]] Result<void> save_sample_pattern(const SamplePattern& pattern, const std::string& path);

/// Loads a saved pattern, refusing one that is malformed or not a valid pattern.
[[nodiscard]] Result<SamplePattern> load_sample_pattern(const std::string& path);

}  // namespace exao
