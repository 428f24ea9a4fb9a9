// raster == bvh, bit for bit, for every pixel (DESIGN.md section 8, test 2), LOD off: the
// influence volumes and the fragment culling tests are conservative. Both backends get the
// raster's own receivers. Cameras inside the room, inside influence volumes, and with triangles
// crossing the near plane; N = 128 and 1024; one- and two-sided triangles; prisms only and
// billboards wherever they fit; and a deliberately shrunk volume to show the test catches leaks.

#include <gtest/gtest.h>

#include <chrono>
#include <iostream>
#include <optional>
#include <string>

#include "bvh/bvh.h"
#include "bvh/occlusion.h"
#include "core/builtin_scenes.h"
#include "core/camera.h"
#include "core/embree_reference.h"
#include "io/polygon_soup_loader.h"
#include "core/sample_pattern.h"
#include "lut/mask_engine.h"
#include "raster/occlusion.h"
#include "tests/test_support.h"

namespace exao::raster {
namespace {

struct SceneSetup {
  Scene scene;
  lut::TriangleSet triangles;
  std::optional<bvh::Bvh> bvh;
  float diagonal = 0.0f;

  explicit SceneSetup(Scene s) : scene(std::move(s)), triangles(lut::TriangleSet::build(scene)), diagonal(scene.bounds().diagonal()) {
    auto built = bvh::Bvh::build(triangles);
    EXPECT_TRUE(built) << built.error().message;
    bvh.emplace(std::move(*built));
  }
};

lut::MaskEngine make_engine(const SceneSetup& s, int n, float radius_fraction, lut::MaskMode mode) {
  auto pattern = make_sample_pattern(n, Falloff::Constant);
  EXPECT_TRUE(pattern);
  auto rays = make_shadow_rays(*pattern, radius_fraction * s.diagonal, kDefaultOffsetFraction * s.diagonal);
  EXPECT_TRUE(rays);
  auto engine = lut::MaskEngine::build(*rays, mode);
  EXPECT_TRUE(engine) << engine.error().message;
  return std::move(*engine);
}

struct Comparison {
  std::size_t receivers = 0, differ = 0, blocked = 0;
  RasterStats stats;
};

Comparison compare(const SceneSetup& s, const lut::MaskEngine& engine, const Camera& camera, int width, int height,
                   const RasterOptions& options = {}) {
  const auto start = std::chrono::steady_clock::now();
  const RasterResult raster = occlusion(s.scene, s.triangles, engine, camera, width, height, options);
  const auto middle = std::chrono::steady_clock::now();
  const MaskSet reference = bvh::occlusion(*s.bvh, engine, raster.pixels.receivers);
  const auto end = std::chrono::steady_clock::now();
  Comparison c;
  c.receivers = raster.masks.size();
  c.stats = raster.stats;
  EXPECT_EQ(reference.size(), raster.masks.size());
  for (std::size_t r = 0; r < c.receivers; ++r) {
    bool same = true;
    for (int w = 0; w < reference.words(); ++w) same = same && reference.row(r)[w] == raster.masks.row(r)[w];
    c.differ += !same;
    c.blocked += static_cast<std::size_t>(reference.blocked_count(r));
  }
  std::cout << s.scene.name << " " << width << "x" << height << " N=" << engine.samples() << " r="
            << engine.rays().radius << " " << lut::mask_mode_name(engine.mode()) << " alpha=" << options.alpha
            << ": " << c.receivers << " receivers, " << c.differ << " differ, blocked " << c.blocked << "; prisms "
            << raster.stats.prisms << ", billboards " << raster.stats.billboards << ", boxes " << raster.stats.boxes
            << ", masks " << raster.stats.masks << "; raster "
            << std::chrono::duration<double>(middle - start).count() << " s, bvh "
            << std::chrono::duration<double>(end - middle).count() << " s\n";
  return c;
}

void expect_equal(const SceneSetup& s, const lut::MaskEngine& engine, const Camera& camera, int width, int height,
                  const RasterOptions& options = {}) {
  const Comparison c = compare(s, engine, camera, width, height, options);
  EXPECT_GT(c.receivers, static_cast<std::size_t>(width * height / 2));
  EXPECT_GT(c.blocked, c.receivers * static_cast<std::size_t>(engine.samples()) / 500) << "too little occlusion to test";
  EXPECT_EQ(c.differ, 0u);
}

Scene two_sided(Scene scene) {
  apply_sidedness(scene, Sidedness::Two);
  scene.name += " (two-sided)";
  return scene;
}

// --- room (one-sided walls, boxes, a sphere) ---------------------------------------------------

// The room's own camera is 0.3 from a wall: inside that wall's prism for r = 5% of the diagonal;
// the walls and floor behind it cross the near plane.
TEST(RasterOcclusion, EqualsBvhInsideRoom) {
  const SceneSetup s(make_room());
  for (const lut::MaskMode mode : {lut::MaskMode::Lut, lut::MaskMode::Exact}) {
    for (const float radius : {0.01f, 0.05f}) {
      expect_equal(s, make_engine(s, 128, radius, mode), s.scene.cameras.at(0), 128, 96);
    }
    expect_equal(s, make_engine(s, 128, 0.2f, mode), s.scene.cameras.at(0), 64, 48);
  }
}

TEST(RasterOcclusion, EqualsBvhWithEveryShape) {
  const SceneSetup s(make_room());
  const lut::MaskEngine engine = make_engine(s, 128, 0.05f, lut::MaskMode::Lut);
  RasterOptions prisms;
  prisms.alpha = 1e-6f;  // a prism for every triangle
  expect_equal(s, engine, s.scene.cameras.at(0), 96, 72, prisms);
  RasterOptions billboards;
  billboards.alpha = 1e6f;  // a billboard wherever the eye is far enough from the sphere
  const Comparison c = compare(s, engine, s.scene.cameras.at(0), 96, 72, billboards);
  EXPECT_EQ(c.differ, 0u);
  EXPECT_GT(c.stats.billboards, c.stats.prisms);
  // Two-sided triangles: the prism's base at r behind, a single billboard polygon.
  const SceneSetup t(two_sided(make_room()));
  const lut::MaskEngine engine2 = make_engine(t, 128, 0.05f, lut::MaskMode::Lut);
  expect_equal(t, engine2, t.scene.cameras.at(0), 96, 72);
  expect_equal(t, engine2, t.scene.cameras.at(0), 96, 72, prisms);
  expect_equal(t, engine2, t.scene.cameras.at(0), 96, 72, billboards);
}

// Receivers the caller already has (here Embree's primary hits) get the same masks as the BVH's.
TEST(RasterOcclusion, EqualsBvhForEmbreeReceivers) {
  const SceneSetup s(make_room());
  const lut::MaskEngine engine = make_engine(s, 128, 0.05f, lut::MaskMode::Lut);
  auto embree = EmbreeScene::build(s.scene);
  ASSERT_TRUE(embree);
  const Camera& camera = s.scene.cameras.at(0);
  const PixelReceivers pixels = pixel_receivers(*embree, s.scene, camera, 96, 72);
  const RasterResult raster = occlusion(pixels, s.scene, s.triangles, engine, camera);
  EXPECT_EQ(raster.pixels.pixel, pixels.pixel);
  EXPECT_EQ(raster.masks.bits(), bvh::occlusion(*s.bvh, engine, pixels.receivers).bits());
}

// Cameras inside influence volumes: in a corner of the box and floor, at the column, under the
// sphere; wide angles so that volumes and triangles cross the near plane and the guard band.
TEST(RasterOcclusion, EqualsBvhWithCameraInsideVolumes) {
  const SceneSetup s(make_room());
  const lut::MaskEngine engine = make_engine(s, 128, 0.05f, lut::MaskMode::Lut);
  const Camera cameras[] = {
      look_at({-0.3f, 0.1f, -0.3f}, {-3.0f, 0.5f, 3.0f}, 100.0f),  // at the box's corner, by the floor
      look_at({3.1f, 1.0f, -2.9f}, {0.0f, 0.5f, 0.0f}, 120.0f),    // at the column's corner
      look_at({1.6f, 0.05f, 1.3f}, {1.6f, 0.9f, 0.6f}, 90.0f),     // under the sphere, looking up at it
      look_at({-4.9f, 3.9f, 3.9f}, {5.0f, 0.0f, -4.0f}, 80.0f),    // in the room's top corner
  };
  for (const Camera& camera : cameras) expect_equal(s, engine, camera, 96, 72);
  RasterOptions prisms;
  prisms.alpha = 1e-6f;
  expect_equal(s, engine, cameras[2], 96, 72, prisms);
}

TEST(RasterOcclusion, EqualsBvhWith1024Rays) {
  const SceneSetup s(make_room());
  expect_equal(s, make_engine(s, 1024, 0.05f, lut::MaskMode::Lut), s.scene.cameras.at(0), 48, 36);
  expect_equal(s, make_engine(s, 1024, 0.1f, lut::MaskMode::Exact), look_at({3.1f, 1.0f, -2.9f}, {0.0f, 0.5f, 0.0f}, 120.0f), 48, 36);
}

// The equality test has teeth. Floor and ceiling 0.99 r apart: the rays of floor receivers
// within 8 degrees of the normal reach the ceiling, so a ceiling prism 2% of r too short loses
// them; with the true volumes (the eye between the planes, inside both) nothing is lost. In the
// room, volumes 20% too small lose bits too.
TEST(RasterOcclusion, ShrunkVolumesAreCaught) {
  const SceneSetup p(make_plane_pair(0.5f, 4.0f));
  const lut::MaskEngine tight = make_engine(p, 128, 0.5f / 0.99f / p.diagonal, lut::MaskMode::Exact);
  expect_equal(p, tight, p.scene.cameras.at(0), 64, 48);
  RasterOptions shrunk;
  shrunk.test_shrink = 0.02f;
  const Comparison c = compare(p, tight, p.scene.cameras.at(0), 64, 48, shrunk);
  EXPECT_GT(c.differ, c.receivers / 4);

  const SceneSetup s(make_room());
  shrunk.test_shrink = 0.2f;
  EXPECT_GT(compare(s, make_engine(s, 128, 0.05f, lut::MaskMode::Lut), s.scene.cameras.at(0), 96, 72, shrunk).differ, 0u);
}

// Stats (Table 2) count every stage without changing a bit; the stages only ever shrink.
TEST(RasterOcclusion, StatsCountStagesWithoutChangingMasks) {
  const SceneSetup s(make_room());
  const lut::MaskEngine engine = make_engine(s, 128, 0.05f, lut::MaskMode::Lut);
  const RasterResult plain = occlusion(s.scene, s.triangles, engine, s.scene.cameras.at(0), 80, 60);
  RasterOptions options;
  options.stats = true;
  std::size_t last = 0, total = 0;
  const RasterResult counted = occlusion(s.scene, s.triangles, engine, s.scene.cameras.at(0), 80, 60, options,
                                         [&](std::size_t done, std::size_t all) {
                                           last = std::max(last, done);
                                           total = all;
                                         });
  EXPECT_EQ(plain.masks.bits(), counted.masks.bits());
  EXPECT_EQ(last, total);
  EXPECT_GT(total, 0u);
  const RasterStats& t = counted.stats;
  std::cout << format_stats(t);
  EXPECT_EQ(t.triangles, s.triangles.size());
  EXPECT_EQ(t.prisms + t.billboards + t.boxes + (t.triangles - t.prisms - t.billboards - t.boxes), t.triangles);
  EXPECT_GE(t.fragments, t.depth_passed);
  EXPECT_GE(t.depth_passed, t.far_depth_passed);
  EXPECT_GE(t.far_depth_passed, t.sphere_passed);
  EXPECT_GE(t.sphere_passed, t.facing_passed);
  EXPECT_GE(t.facing_passed, t.plane_passed);
  EXPECT_GE(t.plane_passed, t.horizon_passed);
  EXPECT_EQ(t.horizon_passed, t.masks + t.full_skipped + t.sphere_mask_skipped);
  EXPECT_GE(t.masks, t.masks_nonempty);
  EXPECT_GT(t.masks_nonempty, 0u);
  EXPECT_GT(t.depth_passed, t.horizon_passed);  // the tests cull something
  EXPECT_LE(plain.stats.masks, t.masks);        // the tile culls only skip work
}

// --- Conference (two-sided OBJ, 330k triangles) ------------------------------------------------

std::optional<SceneSetup> conference() {
  const auto path = test::real_scene("Conference/conference.obj");
  if (path.empty()) return std::nullopt;
  auto scene = load_polygon_soup(path.string());
  EXPECT_TRUE(scene) << scene.error().message;
  if (!scene) return std::nullopt;
  return std::optional<SceneSetup>(std::in_place, std::move(*scene));
}

Camera conference_inside() { return look_at({-900.0f, 350.0f, -950.0f}, {600.0f, 150.0f, 300.0f}, 70.0f); }

TEST(RasterOcclusion, EqualsBvhOnConference) {
  const auto path = test::real_scene("Conference/conference.obj");
  EXAO_REQUIRE_SCENE(path);
  const std::optional<SceneSetup> s = conference();
  ASSERT_TRUE(s);
  for (const float radius : {0.01f, 0.05f}) {
    expect_equal(*s, make_engine(*s, 128, radius, lut::MaskMode::Lut), conference_inside(), 160, 120);
  }
  expect_equal(*s, make_engine(*s, 1024, 0.05f, lut::MaskMode::Lut), conference_inside(), 64, 48);
  // The eye among the chairs, inside the volumes of the table and chairs, wide angle.
  const Camera among_chairs = look_at({0.0f, 120.0f, 0.0f}, {600.0f, 60.0f, -400.0f}, 100.0f);
  const lut::MaskEngine engine = make_engine(*s, 128, 0.05f, lut::MaskMode::Exact);
  expect_equal(*s, engine, among_chairs, 96, 72);
  RasterOptions prisms;
  prisms.alpha = 1e-6f;
  expect_equal(*s, engine, among_chairs, 96, 72, prisms);
}

// One-sided Conference: the facing test and the half-space billboards on a real mesh.
TEST(RasterOcclusion, EqualsBvhOnOneSidedConference) {
  const auto path = test::real_scene("Conference/conference.obj");
  EXAO_REQUIRE_SCENE(path);
  auto scene = load_polygon_soup(path.string());
  ASSERT_TRUE(scene) << scene.error().message;
  apply_sidedness(*scene, Sidedness::One);
  const SceneSetup s(std::move(*scene));
  expect_equal(s, make_engine(s, 128, 0.05f, lut::MaskMode::Lut), conference_inside(), 96, 72);
}

}  // namespace
}  // namespace exao::raster
