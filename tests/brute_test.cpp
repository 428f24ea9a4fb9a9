// The brute backend against Embree (DESIGN.md section 8, test 3): exact masks agree with the ray
// caster on at least 99.99% of rays and on every ray that does not graze (core/grazing.h),
// table masks on at least 99%; and the grid of the brute
// backend changes nothing (it equals the OR over every triangle).

#include <gtest/gtest.h>

#include <chrono>
#include <iostream>
#include <optional>
#include <string>

#include "core/builtin_scenes.h"
#include "core/agreement.h"
#include "core/camera.h"
#include "core/embree_reference.h"
#include "core/grazing.h"
#include "io/polygon_soup_loader.h"
#include "core/pixel_receivers.h"
#include "lut/brute.h"
#include "tests/test_support.h"

namespace exao::lut {
namespace {

struct SceneSetup {
  Scene scene;
  std::optional<EmbreeScene> embree;
  TriangleSet triangles;
  std::vector<Receiver> receivers;
  float diagonal = 0.0f;
};

// Receivers: the pixels of a small image of `camera` that see a triangle.
SceneSetup setup(Scene scene, const Camera& camera, int width, int height) {
  SceneSetup s;
  s.scene = std::move(scene);
  auto embree = EmbreeScene::build(s.scene);
  EXPECT_TRUE(embree) << embree.error().message;
  s.embree.emplace(std::move(*embree));
  s.triangles = TriangleSet::build(s.scene);
  s.receivers = pixel_receivers(*s.embree, s.scene, camera, width, height).receivers;
  // Most pixels must see something, or the test would test little.
  EXPECT_GE(s.receivers.size(), static_cast<std::size_t>(width * height * 9 / 10));
  s.diagonal = s.scene.bounds().diagonal();
  return s;
}

ShadowRays rays_for(const SceneSetup& s, int n, Falloff falloff) {
  auto pattern = make_sample_pattern(n, falloff);
  EXPECT_TRUE(pattern);
  // DESIGN.md: radius 5% of the diagonal here (the test's choice), offset 1e-4 of it (the default).
  auto rays = make_shadow_rays(*pattern, 0.05f * s.diagonal, kDefaultOffsetFraction * s.diagonal);
  EXPECT_TRUE(rays);
  return *rays;
}

struct Agreement {
  std::size_t rays = 0, rays_differ = 0;
  std::size_t receivers = 0, same_ao = 0, same_mask = 0;
  std::size_t blocked_reference = 0, blocked = 0;
  [[nodiscard]] double ray_share() const { return 1.0 - double(rays_differ) / double(rays); }
  [[nodiscard]] double ao_share() const { return double(same_ao) / double(receivers); }
};

Agreement compare(const MaskSet& reference, const MaskSet& masks) {
  Agreement a;
  EXPECT_EQ(reference.size(), masks.size());
  for (std::size_t r = 0; r < reference.size(); ++r) {
    int differ = 0;
    for (int w = 0; w < reference.words(); ++w) differ += std::popcount(reference.row(r)[w] ^ masks.row(r)[w]);
    a.rays += static_cast<std::size_t>(reference.samples());
    a.rays_differ += static_cast<std::size_t>(differ);
    ++a.receivers;
    a.same_ao += reference.blocked_count(r) == masks.blocked_count(r);
    a.same_mask += differ == 0;
    a.blocked_reference += static_cast<std::size_t>(reference.blocked_count(r));
    a.blocked += static_cast<std::size_t>(masks.blocked_count(r));
  }
  return a;
}

// Brute (both modes) against Embree for N = 128 and 1024, constant and linear falloff.
void check_against_embree(const SceneSetup& s, const std::string& name) {
  for (const int n : {128, 1024}) {
    for (const Falloff falloff : {Falloff::Constant, Falloff::Linear}) {
      const ShadowRays rays = rays_for(s, n, falloff);
      const MaskSet reference = s.embree->occlusion(rays, s.receivers);
      for (const MaskMode mode : {MaskMode::Exact, MaskMode::Lut}) {
        auto engine = MaskEngine::build(rays, mode);
        ASSERT_TRUE(engine) << engine.error().message;
        const auto start = std::chrono::steady_clock::now();
        const MaskSet masks = brute_occlusion(*engine, s.triangles, s.receivers);
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        const Agreement a = compare(reference, masks);
        const std::string label =
            name + " N=" + std::to_string(n) + " " + falloff_name(falloff) + " " + mask_mode_name(mode);
        std::cout << label << ": " << a.receivers << " receivers, rays agree " << 100.0 * a.ray_share() << "% ("
                  << a.rays_differ << " of " << a.rays << " differ; blocked " << a.blocked << " vs embree "
                  << a.blocked_reference << "), identical AO " << 100.0 * a.ao_share() << "%, identical masks "
                  << 100.0 * double(a.same_mask) / double(a.receivers) << "%, brute " << seconds << " s\n";
        ::testing::Test::RecordProperty(label + " ray agreement %", std::to_string(100.0 * a.ray_share()));
        ::testing::Test::RecordProperty(label + " identical AO %", std::to_string(100.0 * a.ao_share()));
        EXPECT_GT(a.blocked_reference, a.rays / 100) << label << ": too little occlusion to test anything";
        EXPECT_GE(a.ray_share(), mode == MaskMode::Exact ? 0.9999 : 0.99) << label;
        if (mode == MaskMode::Exact) {
          // Only grazing rays may differ (core/grazing.h, docs/surface-rule.md).
          const GrazingTest grazing(s.scene, rays);
          const exao::Agreement g = compare_masks(reference, masks, s.receivers, rays, &grazing);
          std::cout << "  " << g.rays_differ_grazing << " of the " << g.rays_differ << " differing rays graze; "
                    << g.receivers_grazing << " receivers differ only by grazing rays\n";
          EXPECT_EQ(g.rays_differ_not_grazing(), 0u) << label;
        }
      }
    }
  }
}

TEST(Brute, MatchesEmbreeOnRoom) {
  Scene scene = make_room();
  const Camera camera = scene.cameras.at(0);
  const SceneSetup s = setup(std::move(scene), camera, 32, 24);
  check_against_embree(s, "room");
}

// An eye above the middle of the conference room, looking down at the table and chairs:
// every pixel sees geometry within a few radii.
Camera conference_camera() { return look_at({0.0f, 300.0f, 0.0f}, {600.0f, 100.0f, -400.0f}, 60.0f); }

TEST(Brute, MatchesEmbreeOnConference) {
  const auto path = test::real_scene("Conference/conference.obj");
  EXAO_REQUIRE_SCENE(path);
  auto scene = load_polygon_soup(path.string());
  ASSERT_TRUE(scene) << scene.error().message;
  const SceneSetup s = setup(std::move(*scene), conference_camera(), 32, 24);
  check_against_embree(s, "conference");
}

// The grid skips only triangles that triangle_mask rejects: brute == OR over every triangle.
void check_grid(const SceneSetup& s, std::size_t receivers) {
  const std::span<const Receiver> some(s.receivers.data(), std::min(receivers, s.receivers.size()));
  for (const Falloff falloff : {Falloff::Constant, Falloff::Linear}) {
    const ShadowRays rays = rays_for(s, 128, falloff);
    for (const MaskMode mode : {MaskMode::Exact, MaskMode::Lut}) {
      auto engine = MaskEngine::build(rays, mode);
      ASSERT_TRUE(engine);
      const MaskSet gridded = brute_occlusion(*engine, s.triangles, some);
      const MaskSet every = brute_occlusion_every_triangle(*engine, s.triangles, some);
      EXPECT_EQ(gridded.bits(), every.bits()) << mask_mode_name(mode);
      std::size_t blocked = 0;
      for (std::size_t r = 0; r < gridded.size(); ++r) blocked += static_cast<std::size_t>(gridded.blocked_count(r));
      EXPECT_GT(blocked, 0u);
    }
  }
}

TEST(Brute, GridEqualsEveryTriangleOnRoom) {
  Scene scene = make_room();
  const Camera camera = scene.cameras.at(0);
  check_grid(setup(std::move(scene), camera, 16, 12), 192);
}

TEST(Brute, GridEqualsEveryTriangleOnConference) {
  const auto path = test::real_scene("Conference/conference.obj");
  EXAO_REQUIRE_SCENE(path);
  auto scene = load_polygon_soup(path.string());
  ASSERT_TRUE(scene) << scene.error().message;
  check_grid(setup(std::move(*scene), conference_camera(), 8, 6), 48);
}

TEST(Brute, ReportsProgressAndHandlesNoReceivers) {
  Scene scene = make_plane_pair(0.5f, 4.0f);
  const TriangleSet triangles = TriangleSet::build(scene);
  auto pattern = make_sample_pattern(64, Falloff::Constant);
  ASSERT_TRUE(pattern);
  auto rays = make_shadow_rays(*pattern, 1.0f, 1e-4f);
  ASSERT_TRUE(rays);
  auto engine = MaskEngine::build(*rays, MaskMode::Exact);
  ASSERT_TRUE(engine);
  EXPECT_EQ(brute_occlusion(*engine, triangles, {}).size(), 0u);
  // The analytic case of DESIGN.md section 6: a point under a parallel plane at height h < r
  // with constant falloff has AO = (h / r)^2 (within the pattern's sampling error).
  std::vector<Receiver> receivers(64);
  for (std::size_t i = 0; i < receivers.size(); ++i) {
    receivers[i].position = {0.01f * static_cast<float>(i % 8), 0.0f, 0.01f * static_cast<float>(i / 8)};
    receivers[i].normal = {0.0f, 1.0f, 0.0f};
    receivers[i].key = i;
  }
  std::atomic<std::size_t> last{0};
  const MaskSet masks = brute_occlusion(*engine, triangles, receivers, [&](std::size_t done, std::size_t total) {
    EXPECT_EQ(total, receivers.size());
    last = std::max<std::size_t>(last, done);
  });
  EXPECT_EQ(last, receivers.size());
  double ao = 0.0;
  for (std::size_t r = 0; r < masks.size(); ++r) ao += masks.ao(r);
  ao /= static_cast<double>(masks.size());
  const double h = 0.5 - 1e-4;
  EXPECT_NEAR(ao, h * h, 0.03);
}

}  // namespace
}  // namespace exao::lut
