// Property tests of the shared sample pattern (DESIGN.md section 2).

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <numeric>

#include "core/random.h"
#include "core/sample_pattern.h"
#include "tests/test_support.h"

namespace exao {
namespace {

const int kCounts[] = {32, 64, 128, 256, 512, 1024};

SamplePattern pattern(int n, Falloff falloff = Falloff::Constant, std::uint64_t seed = kDefaultPatternSeed) {
  Result<SamplePattern> p = make_sample_pattern(n, falloff, seed);
  EXPECT_TRUE(p.has_value());
  return *p;
}

// Smallest distance between two points' projections on the disc.
double min_spacing(const std::vector<glm::dvec2>& points) {
  double best = INFINITY;
  for (std::size_t i = 0; i < points.size(); ++i)
    for (std::size_t j = i + 1; j < points.size(); ++j) best = std::min(best, glm::length(points[i] - points[j]));
  return best;
}

// Largest gap between the share of points inside a disc of radius sqrt(c) and c (for uniform
// density on the unit disc, the share is c), over every c: a radial discrepancy.
double radial_discrepancy(const std::vector<glm::dvec2>& points) {
  std::vector<double> r2;
  for (const auto& p : points) r2.push_back(glm::dot(p, p));
  std::sort(r2.begin(), r2.end());
  const double n = static_cast<double>(r2.size());
  double worst = 0.0;
  for (std::size_t i = 0; i < r2.size(); ++i) {
    const double k = static_cast<double>(i);
    worst = std::max({worst, std::abs((k + 1) / n - r2[i]), std::abs(k / n - r2[i])});
  }
  return worst;
}

// Mean gap between the share of points on one side of a random chord and that side's share of
// the disc's area, over many chords: how well the set estimates the area of a cut-off region,
// which is what an occluding plane does to the hemisphere.
double chord_discrepancy(const std::vector<glm::dvec2>& points) {
  Rng rng(77);
  const int chords = 4000;
  double total = 0.0;
  for (int c = 0; c < chords; ++c) {
    const double angle = 2.0 * M_PI * rng.uniform();
    const double offset = 2.0 * rng.uniform() - 1.0;  // signed distance of the chord from the centre
    const glm::dvec2 normal(std::cos(angle), std::sin(angle));
    const double inside = static_cast<double>(std::count_if(points.begin(), points.end(), [&](const glm::dvec2& p) {
      return glm::dot(p, normal) >= offset;
    }));
    // Area of the disc segment beyond the chord, over the disc's area.
    const double area = (std::acos(offset) - offset * std::sqrt(1.0 - offset * offset)) / M_PI;
    total += std::abs(inside / static_cast<double>(points.size()) - area);
  }
  return total / chords;
}

std::vector<glm::dvec2> disc(const SamplePattern& p) {
  std::vector<glm::dvec2> out;
  for (const glm::vec3& d : p.directions) out.emplace_back(d.x, d.y);
  return out;
}

std::vector<glm::dvec2> random_disc(int n, std::uint64_t seed) {
  Rng rng(seed);
  std::vector<glm::dvec2> out;
  while (static_cast<int>(out.size()) < n) {
    const glm::dvec2 p(2 * rng.uniform() - 1, 2 * rng.uniform() - 1);
    if (glm::dot(p, p) < 1) out.push_back(p);
  }
  return out;
}

TEST(SamplePattern, DirectionsAreUnitAboveHorizonAndCosineWeighted) {
  for (const int n : kCounts) {
    const SamplePattern p = pattern(n);
    ASSERT_EQ(p.count, n);
    ASSERT_EQ(p.directions.size(), static_cast<std::size_t>(n));
    double mean_cos = 0.0;
    for (const glm::vec3& d : p.directions) {
      EXPECT_NEAR(glm::length(d), 1.0f, 1e-6f);
      EXPECT_GT(d.z, 0.0f);
      mean_cos += d.z;
    }
    mean_cos /= n;
    // Cosine-weighted directions have E[cos] = 2/3; a stratified set gets there much faster than
    // the 0.24/sqrt(N) of independent samples.
    EXPECT_NEAR(mean_cos, 2.0 / 3.0, 0.1 * 0.24 / std::sqrt(n)) << "N = " << n;
    EXPECT_GT(p.min_elevation, 0.0f);
  }
}

TEST(SamplePattern, BetterStratifiedThanRandomPoints) {
  for (const int n : kCounts) {
    const std::vector<glm::dvec2> ours = disc(pattern(n));
    double random_spacing = 0.0, random_discrepancy = 0.0, random_chord = 0.0;
    const int trials = 8;
    for (int t = 0; t < trials; ++t) {
      const auto r = random_disc(n, 1000 + t);
      random_spacing += min_spacing(r) / trials;
      random_discrepancy += radial_discrepancy(r) / trials;
      random_chord += chord_discrepancy(r) / trials;
    }
    // Lloyd relaxation spreads points apart: the closest pair is far further apart than in a
    // random set, and the density is far closer to uniform.
    EXPECT_GT(min_spacing(ours), 4.0 * random_spacing) << "N = " << n;
    EXPECT_LT(radial_discrepancy(ours), 0.5 * random_discrepancy) << "N = " << n;
    EXPECT_LT(chord_discrepancy(ours), 0.5 * random_chord) << "N = " << n;
  }
}

TEST(SamplePattern, DeterministicPerSeed) {
  // Two independent builds (no cache), as two processes would make them.
  const SamplePattern a = build_sample_pattern(256, Falloff::Linear, 7);
  const SamplePattern b = build_sample_pattern(256, Falloff::Linear, 7);
  const SamplePattern c = pattern(256, Falloff::Linear, 8);
  EXPECT_EQ(a.directions, b.directions);
  EXPECT_EQ(a.lengths, b.lengths);
  EXPECT_NE(a.directions, c.directions);
}

TEST(SamplePattern, FalloffLengthsMatchTheFalloff) {
  // Eq. 3 equals Eq. 2 when P(l >= D) = rho(D) for every occluder distance D.
  const int n = 1024;
  const struct { Falloff falloff; double (*rho)(double); } cases[] = {
      {Falloff::Constant, [](double) { return 1.0; }},
      {Falloff::Linear, [](double d) { return 1.0 - d; }},
      {Falloff::Quadratic, [](double d) { return (1.0 - d) * (1.0 - d); }},
  };
  for (const auto& c : cases) {
    const SamplePattern p = pattern(n, c.falloff);
    for (const float l : p.lengths) {
      EXPECT_GT(l, 0.0f);
      EXPECT_LE(l, 1.0f);
    }
    for (double d = 0.05; d < 1.0; d += 0.1) {
      const auto reach = std::count_if(p.lengths.begin(), p.lengths.end(), [&](float l) { return l >= d; });
      // Stratified levels: off by at most one stratum.
      EXPECT_NEAR(static_cast<double>(reach) / n, c.rho(d), 1.5 / n) << falloff_name(c.falloff) << " D = " << d;
    }
  }
}

TEST(SamplePattern, RejectsCountsThatAreNotMultiplesOf32) {
  for (const int n : {0, 16, 100, 1056, -32}) {
    Result<SamplePattern> p = make_sample_pattern(n, Falloff::Constant);
    ASSERT_FALSE(p.has_value()) << n;
    EXPECT_NE(p.error().message.find(std::to_string(n)), std::string::npos);
  }
}

TEST(SamplePattern, SaveLoadRoundTrip) {
  test::TempDir dir;
  const SamplePattern p = pattern(128, Falloff::Quadratic, 99);
  const std::string path = (dir / "pattern.txt").string();
  ASSERT_TRUE(save_sample_pattern(p, path).has_value());
  Result<SamplePattern> loaded = load_sample_pattern(path);
  ASSERT_TRUE(loaded.has_value()) << loaded.error().message;
  EXPECT_EQ(loaded->count, p.count);
  EXPECT_EQ(loaded->falloff, p.falloff);
  EXPECT_EQ(loaded->seed, p.seed);
  EXPECT_EQ(loaded->directions, p.directions);
  EXPECT_EQ(loaded->lengths, p.lengths);
  EXPECT_EQ(loaded->points, p.points);
  EXPECT_EQ(loaded->min_elevation, p.min_elevation);
}

TEST(SamplePattern, LoadRefusesDamagedFiles) {
  test::TempDir dir;
  const std::string path = (dir / "pattern.txt").string();
  ASSERT_TRUE(save_sample_pattern(pattern(64), path).has_value());
  std::ifstream in(path);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string damaged[] = {
      "",                                               // empty
      "hello world\n",                                  // not a pattern
      text.substr(0, text.size() / 2),                  // truncated
      "exao-sample-pattern 1\nsamples 48\nfalloff constant\nseed 1\n",  // bad N
      text + "0 0 1 1\n",                               // extra data
  };
  for (const std::string& contents : damaged) {
    test::write_file(path, contents);
    Result<SamplePattern> loaded = load_sample_pattern(path);
    ASSERT_FALSE(loaded.has_value());
    EXPECT_NE(loaded.error().message.find(path), std::string::npos) << loaded.error().message;
    EXPECT_EQ(loaded.error().message.find('\n'), std::string::npos);
  }
  EXPECT_FALSE(load_sample_pattern((dir / "missing.txt").string()).has_value());
}

}  // namespace
}  // namespace exao
