// Exact at every radius the library accepts (issue 22): from 1e-6 of the scene's diagonal up to
// 1e17, bvh, brute and raster with exact masks equal Embree on every ray that does not graze
// (core/grazing.h), on the built-in room and on Conference, for constant and linear falloff.
// Before the fix the masks, normalised by 1/r, underflowed at radii far beyond the scene: a
// point inside the closed room came out fully open (AO 1) at r = 1e8..1e16, where Embree says 0.
//
// Grazing is judged on rays equivalent to the engine's (the same directions, lengths
// min(l_i r, R) with R = twice the occluders' diagonal plus the offset): no segment from a
// receiver on the scene's surface reaches geometry beyond R, so both hit the same triangles,
// and GrazingTest's tolerance, which grows with the radius, stays that of a scene-sized ray.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iostream>
#include <random>
#include <string>
#include <vector>

#include "core/agreement.h"
#include "core/builtin_scenes.h"
#include "core/camera.h"
#include "core/grazing.h"
#include "io/load_scene.h"
#include "engine/engine.h"
#include "tests/test_support.h"

namespace exao {
namespace {

// Points on the scene's triangles (area-agnostic: uniform over triangles), normal to the
// front or, at random, the back face; keys 0, 1, 2, ...
std::vector<Receiver> surface_points(const Scene& scene, int count, std::uint32_t seed) {
  std::mt19937 random(seed);
  std::uniform_int_distribution<std::size_t> pick(0, scene.triangle_count() - 1);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  std::vector<Receiver> out;
  while (static_cast<int>(out.size()) < count) {
    const auto [a, b, c] = scene.triangle(pick(random));
    float u = unit(random), v = unit(random);
    if (u + v > 1.0f) u = 1.0f - u, v = 1.0f - v;
    glm::vec3 n = glm::cross(b - a, c - a);
    if (!(glm::dot(n, n) > 1e-20f)) continue;
    if (unit(random) < 0.5f) n = -n;
    out.push_back({a + u * (b - a) + v * (c - a), glm::normalize(n), out.size()});
  }
  return out;
}

engine::Engine build(const Scene& scene, engine::Method method, float radius, Falloff falloff, int samples,
                     engine::Receivers receivers = engine::Receivers::Points) {
  engine::Options options;
  options.method = method;
  options.radius = {radius, false};
  options.falloff = falloff;
  options.samples = samples;
  options.masks = lut::MaskMode::Exact;
  Result<engine::Engine> built = engine::Engine::build(scene, options, receivers);
  EXPECT_TRUE(built) << built.error().message;
  return std::move(*built);
}

// The rays of `rays` with every length capped at `reach` (world units): for receivers within
// `reach` of all geometry they hit exactly what the originals hit.
ShadowRays capped(const ShadowRays& rays, double reach) {
  if (static_cast<double>(rays.radius) <= reach) return rays;
  ShadowRays out = rays;
  out.radius = static_cast<float>(reach);
  const double scale = static_cast<double>(rays.radius) / reach;
  for (std::size_t i = 0; i < out.pattern.lengths.size(); ++i) {
    out.pattern.lengths[i] = static_cast<float>(std::min(1.0, static_cast<double>(out.pattern.lengths[i]) * scale));
    out.pattern.points[i] = out.pattern.directions[i] * out.pattern.lengths[i];
  }
  return out;
}

struct Case {
  const char* label;
  engine::Method method;
};

// Every ray of `masks` equals Embree's `reference` unless it grazes.
void expect_exact(const Scene& scene, const MaskSet& reference, const MaskSet& masks, std::span<const Receiver> receivers,
                  const ShadowRays& rays, const std::string& label) {
  const double reach = 2.0 * static_cast<double>(scene.bounds().diagonal()) + rays.origin_offset;
  const ShadowRays equivalent = capped(rays, reach);
  const GrazingTest grazing(scene, equivalent);
  const Agreement a = compare_masks(reference, masks, receivers, equivalent, &grazing);
  EXPECT_EQ(a.rays_differ_not_grazing(), 0u) << label << ": " << a.rays_differ << " rays differ, "
                                              << a.rays_differ_grazing << " of them graze";
  if (a.rays_differ) std::cout << "  " << label << ": " << a.rays_differ_grazing << " grazing rays differ\n";
}

// Radii from 1e-6 of the diagonal to the limit of 1e17: small, the default, beyond the scene,
// and the huge ones renderers pass to mean "unbounded".
std::vector<float> radii(float diagonal) {
  return {1e-6f * diagonal, 1e-3f * diagonal, 0.05f * diagonal, 10.0f * diagonal, 1e4f, 1e8f, 1e12f, 1e16f, 1e17f};
}

void check_points(const Scene& scene, const std::vector<Receiver>& receivers, const std::vector<Case>& cases,
                  const std::string& name) {
  const float diagonal = scene.bounds().diagonal();
  for (const Falloff falloff : {Falloff::Constant, Falloff::Linear}) {
    for (const float r : radii(diagonal)) {
      const std::string where = name + " r=" + std::to_string(r) + " " + falloff_name(falloff);
      const engine::Engine embree = build(scene, engine::Method::Embree, r, falloff, 128);
      const Result<MaskSet> reference = embree.masks(receivers);
      ASSERT_TRUE(reference) << reference.error().message;
      for (const Case& c : cases) {
        const engine::Engine engine = build(scene, c.method, r, falloff, 128);
        const Result<MaskSet> masks = engine.masks(receivers);
        ASSERT_TRUE(masks) << masks.error().message;
        expect_exact(scene, *reference, *masks, receivers, embree.rays(), where + " " + c.label);
        // Single queries take the same path as batches.
        std::vector<std::uint64_t> words(engine.mask_words());
        engine.mask_one(receivers.front(), words);
        EXPECT_TRUE(std::equal(words.begin(), words.end(), masks->row(0).begin())) << where << " " << c.label << " single";
      }
    }
  }
}

void check_pixels(const Scene& scene, const Camera& camera, int width, int height, const std::string& name) {
  const float diagonal = scene.bounds().diagonal();
  for (const float r : radii(diagonal)) {
    const std::string where = name + " r=" + std::to_string(r) + " raster";
    const engine::Engine raster = build(scene, engine::Method::Raster, r, Falloff::Constant, 128, engine::Receivers::Pixels);
    Result<engine::PixelResult> rendered = raster.render(camera, width, height);
    ASSERT_TRUE(rendered) << rendered.error().message;
    ASSERT_GT(rendered->pixels.receivers.size(), 0u);
    const engine::Engine embree = build(scene, engine::Method::Embree, r, Falloff::Constant, 128);
    const Result<MaskSet> reference = embree.masks(rendered->pixels.receivers);
    ASSERT_TRUE(reference) << reference.error().message;
    expect_exact(scene, *reference, rendered->masks, rendered->pixels.receivers, embree.rays(), where);
  }
}

// The case of the issue: inside the closed room every ray is blocked at every radius beyond
// the room, so AO is exactly 0 (it was 1 at r = 1e8 and beyond).
TEST(LargeRadius, InsideTheClosedRoomAoIsZero) {
  const Scene room = make_room();
  const Receiver inside{{0.3f, 1.7f, 0.2f}, {0.0f, 1.0f, 0.0f}, 7};
  for (const engine::Method method : {engine::Method::Bvh, engine::Method::Brute, engine::Method::Embree}) {
    for (const float r : {1e2f, 1e6f, 1e8f, 1e10f, 1e16f, 1e17f}) {
      const engine::Engine engine = build(room, method, r, Falloff::Constant, 128);
      const Result<std::vector<float>> ao = engine.ao(std::span<const Receiver>(&inside, 1));
      ASSERT_TRUE(ao) << ao.error().message;
      EXPECT_EQ(ao->at(0), 0.0f) << engine::method_name(method) << " r=" << r;
    }
  }
}

TEST(LargeRadius, RoomPointsMatchEmbreeAtEveryRadius) {
  const Scene room = make_room();
  check_points(room, surface_points(room, 48, 1), {{"bvh", engine::Method::Bvh}, {"brute", engine::Method::Brute}}, "room");
}

TEST(LargeRadius, RoomPixelsMatchEmbreeAtEveryRadius) {
  const Scene room = make_room();
  check_pixels(room, room.cameras.at(0), 24, 16, "room");
}

TEST(LargeRadius, ConferencePointsMatchEmbreeAtEveryRadius) {
  const auto path = test::real_scene("Conference/conference.obj");
  EXAO_REQUIRE_SCENE(path);
  Result<Scene> scene = open_scene(path.string());
  ASSERT_TRUE(scene) << scene.error().message;
  check_points(*scene, surface_points(*scene, 24, 2), {{"bvh", engine::Method::Bvh}, {"brute", engine::Method::Brute}},
               "Conference");
}

TEST(LargeRadius, ConferencePixelsMatchEmbreeAtEveryRadius) {
  const auto path = test::real_scene("Conference/conference.obj");
  EXAO_REQUIRE_SCENE(path);
  Result<Scene> scene = open_scene(path.string());
  ASSERT_TRUE(scene) << scene.error().message;
  check_pixels(*scene, look_at({-900.0f, 350.0f, -950.0f}, {600.0f, 150.0f, 300.0f}, 70.0f), 12, 8, "Conference");
}

}  // namespace
}  // namespace exao
