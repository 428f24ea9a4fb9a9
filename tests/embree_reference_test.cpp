// The Embree reference against analytic answers and the sidedness rules (DESIGN.md sections 1, 8.4).

#include <gtest/gtest.h>

#include <cmath>

#include "core/builtin_scenes.h"
#include "core/embree_reference.h"
#include "core/pixel_receivers.h"
#include "core/random.h"

namespace exao {
namespace {

ShadowRays rays_for(int n, float radius, float offset, Falloff falloff = Falloff::Constant) {
  Result<SamplePattern> pattern = make_sample_pattern(n, falloff);
  EXPECT_TRUE(pattern.has_value());
  Result<ShadowRays> rays = make_shadow_rays(*pattern, radius, offset);
  EXPECT_TRUE(rays.has_value());
  return *rays;
}

// Receivers scattered near the centre of the plane-pair floor, far from the edges.
std::vector<Receiver> floor_receivers(int count) {
  Rng rng(5);
  std::vector<Receiver> out;
  for (int i = 0; i < count; ++i) {
    out.push_back({{static_cast<float>(rng.uniform() - 0.5), 0.0f, static_cast<float>(rng.uniform() - 0.5)},
                   {0.0f, 1.0f, 0.0f},
                   static_cast<std::uint64_t>(i)});
  }
  return out;
}

// The spread a stratified pattern of N points leaves on a disc-shaped region: a few points
// along the boundary circle, ~ N^(1/2) of them, can fall either way: 1.5 / sqrt(N).
double sampling_error(int n) { return 1.5 / std::sqrt(static_cast<double>(n)); }

TEST(EmbreeReference, PlanePairMatchesAnalyticAO) {
  const float radius = 1.0f;
  const float offset = 1e-4f;
  for (const float h : {0.2f, 0.5f, 0.8f}) {
    const Scene scene = make_plane_pair(h, 4.0f);
    Result<EmbreeScene> embree = EmbreeScene::build(scene);
    ASSERT_TRUE(embree.has_value());
    const std::vector<Receiver> receivers = floor_receivers(200);
    for (const int n : {128, 1024}) {
      const ShadowRays rays = rays_for(n, radius, offset);
      const MaskSet masks = embree->occlusion(rays, receivers);
      // A ray of length r at angle theta from the normal reaches the ceiling iff r cos(theta) >= h';
      // for cosine-weighted directions P(cos >= c) = 1 - c^2, so AO = (h'/r)^2.
      const double expected = std::pow((h - offset) / radius, 2.0);
      double mean = 0.0;
      for (std::size_t i = 0; i < receivers.size(); ++i) {
        EXPECT_NEAR(masks.ao(i), expected, sampling_error(n)) << "h = " << h << " N = " << n << " receiver " << i;
        mean += masks.ao(i) / static_cast<double>(receivers.size());
      }
      // Jittered frames average the boundary error away: the mean is much tighter.
      EXPECT_NEAR(mean, expected, 0.25 * sampling_error(n)) << "h = " << h << " N = " << n;
    }
  }
}

TEST(EmbreeReference, OneSidedTrianglesBlockOnlyFromTheirFront) {
  const Receiver receiver{{0.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}, 7};
  const ShadowRays rays = rays_for(128, 1.0f, 1e-4f);
  // A large triangle at height 0.3 above the receiver, in both windings.
  const glm::vec3 a{-10.0f, 0.3f, -10.0f}, b{10.0f, 0.3f, -10.0f}, c{0.0f, 0.3f, 10.0f};
  for (const bool faces_down : {true, false}) {
    for (const bool two_sided : {false, true}) {
      Scene scene;
      if (faces_down) {
        scene.add_triangle(a, b, c, two_sided, 0);  // cross(b-a, c-a) points -Y: front toward the receiver
      } else {
        scene.add_triangle(a, c, b, two_sided, 0);
      }
      ASSERT_EQ(scene.triangle_count(), 1u);
      Result<EmbreeScene> embree = EmbreeScene::build(scene);
      ASSERT_TRUE(embree.has_value());
      const MaskSet masks = embree->occlusion(rays, std::span(&receiver, 1));
      const bool should_block = faces_down || two_sided;
      if (should_block) {
        EXPECT_GT(masks.blocked_count(0), 100) << "faces_down " << faces_down << " two_sided " << two_sided;
      } else {
        EXPECT_EQ(masks.blocked_count(0), 0) << "faces_down " << faces_down << " two_sided " << two_sided;
      }
    }
  }
}

TEST(EmbreeReference, EveryRayModeGivesTheSameMasks) {
  const Scene scene = make_room();
  Result<EmbreeScene> embree = EmbreeScene::build(scene);
  ASSERT_TRUE(embree.has_value());
  const PixelReceivers pixels = pixel_receivers(*embree, scene, scene.cameras[0], 64, 48);
  ASSERT_GT(pixels.receivers.size(), 3000u);
  const ShadowRays rays = rays_for(128, 0.05f * scene.bounds().diagonal(), 1e-4f * scene.bounds().diagonal());
  EmbreeOptions options;
  options.rays = EmbreeRays::Single;
  const MaskSet reference = embree->occlusion(rays, pixels.receivers, options);
  std::size_t blocked = 0;
  for (std::size_t i = 0; i < reference.size(); ++i) blocked += static_cast<std::size_t>(reference.blocked_count(i));
  EXPECT_GT(blocked, reference.size() * 5) << "the room should occlude something";
  for (const EmbreeRays mode : {EmbreeRays::Packet4, EmbreeRays::Packet8, EmbreeRays::Packet16}) {
    for (const bool across : {false, true}) {
      options.rays = mode;
      options.across_receivers = across;
      const MaskSet masks = embree->occlusion(rays, pixels.receivers, options);
      std::size_t differ = 0;
      for (std::size_t i = 0; i < masks.size(); ++i)
        for (int r = 0; r < rays.count(); ++r) differ += masks.blocked(i, r) != reference.blocked(i, r);
      // The same watertight test in every width; only a ray grazing an edge could differ.
      EXPECT_LE(differ, masks.size() * static_cast<std::size_t>(rays.count()) / 100000)
          << embree_rays_name(mode) << (across ? " across receivers" : " per receiver");
    }
  }
}

TEST(EmbreeReference, PixelReceiversFaceTheCamera) {
  const Scene scene = make_room();
  Result<EmbreeScene> embree = EmbreeScene::build(scene);
  ASSERT_TRUE(embree.has_value());
  const Camera& camera = scene.cameras[0];
  const PixelReceivers pixels = pixel_receivers(*embree, scene, camera, 32, 24);
  EXPECT_EQ(pixels.receivers.size(), 32u * 24u) << "a closed room: every pixel sees a wall";
  for (std::size_t i = 0; i < pixels.receivers.size(); ++i) {
    const Receiver& r = pixels.receivers[i];
    EXPECT_EQ(r.key, pixels.pixel[i]);
    EXPECT_LT(glm::dot(r.normal, r.position - camera.eye), 0.0f);
    EXPECT_NEAR(glm::length(r.normal), 1.0f, 1e-5f);
  }
}

}  // namespace
}  // namespace exao
