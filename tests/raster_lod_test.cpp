// Level of detail for the raster backend (paper Sec. 4.3; raster/lod.h, raster/distance_range.h):
//  - every simplified level stays within its eps of the original (sampled two-sided Hausdorff
//    distance), keeps sidedness and really simplifies;
//  - a distance range split in two, [0, a] and [a, r], gives the same mask as [0, r], for one
//    triangle and receiver (range_mask) and through the whole raster pipeline, whose influence
//    volumes are then built with r_max = a;
//  - the engine (engine::Options::lod): levels built once per geometry and shared by its
//    engines, the ranges really reach the raster backend, LOD refused for any other method;
//  - bad LOD options get one-line errors.
// With LOD off, raster == bvh bit for bit is raster_occlusion_test's.

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <memory>
#include <random>
#include <string>
#include <sys/wait.h>

#include "core/builtin_scenes.h"
#include "core/sample_pattern.h"
#include "engine/engine.h"
#include "lut/mask_engine.h"
#include "raster/distance_range.h"
#include "raster/gbuffer.h"
#include "raster/lod.h"
#include "raster/occlusion.h"
#include "tests/test_support.h"

namespace exao::raster {
namespace {

using test::CommandResult;
using test::expect_one_line_error;

CommandResult exao(const std::string& arguments) { return test::run_exao(EXAO_BINARY, arguments); }


// A finely tessellated wavy sheet and a closed sphere: surfaces that simplify well, with a
// border (the sheet) and without (the sphere).
Scene make_lod_scene(bool two_sided, int grid = 32) {
  Scene s;
  s.name = "lod test";
  const int kGrid = grid;
  auto height = [](float x, float z) { return 0.15f * std::sin(3.0f * x) * std::cos(2.0f * z); };
  auto point = [&](int i, int j) {
    const float x = -2.0f + 4.0f * float(i) / float(kGrid), z = -2.0f + 4.0f * float(j) / float(kGrid);
    return glm::vec3(x, height(x, z), z);
  };
  for (int i = 0; i < kGrid; ++i) {
    for (int j = 0; j < kGrid; ++j) {
      s.add_triangle(point(i, j), point(i, j + 1), point(i + 1, j), two_sided, -1);
      s.add_triangle(point(i + 1, j), point(i, j + 1), point(i + 1, j + 1), two_sided, -1);
    }
  }
  const int kRings = grid / 2, kSegments = grid;
  auto sphere = [&](int ring, int segment) {
    const float theta = 3.14159265f * float(ring) / float(kRings), phi = 6.2831853f * float(segment % kSegments) / float(kSegments);
    return glm::vec3(0.5f * std::sin(theta) * std::cos(phi), 0.8f + 0.5f * std::cos(theta), 0.5f * std::sin(theta) * std::sin(phi));
  };
  for (int ring = 0; ring < kRings; ++ring) {
    for (int segment = 0; segment < kSegments; ++segment) {
      // Outward, counter-clockwise seen from outside.
      if (ring > 0) s.add_triangle(sphere(ring, segment), sphere(ring, segment + 1), sphere(ring + 1, segment), two_sided, -1);
      if (ring + 1 < kRings) s.add_triangle(sphere(ring, segment + 1), sphere(ring + 1, segment + 1), sphere(ring + 1, segment), two_sided, -1);
    }
  }
  return s;
}

// Only the envelope filter bounds the error of the faces: Bounded_distance_placement checks the
// new vertex alone, and on this scene its level 3 is 0.15 from the original for eps 0.036.
void expect_levels_within_eps(const Scene& scene, LodFilter filter) {
  LodOptions options;
  options.eps1 = 0.004f;
  options.levels = 3;
  options.k = 3.0f;
  options.filter = filter;
  const float radius = 1.0f;
  auto lod = build_lod(scene, radius, options);
  ASSERT_TRUE(lod) << lod.error().message;
  ASSERT_EQ(lod->levels.size(), 4u);
  EXPECT_EQ(lod->kept_triangles, 0u) << "these surfaces are manifold";
  const std::vector<glm::vec3> original = level_triangles(*lod, 0, true);
  ASSERT_EQ(original.size(), 3 * scene.triangle_count());
  std::size_t previous = scene.triangle_count();
  for (int i = 1; i <= 3; ++i) {
    const LodLevel& level = lod->levels[static_cast<std::size_t>(i)];
    const std::vector<glm::vec3> simplified = level_triangles(*lod, i, false);
    ASSERT_FALSE(simplified.empty());
    EXPECT_LT(level.triangles, previous) << "level " << i << " simplified nothing";
    previous = level.triangles;
    const double there = sampled_distance(simplified, original, 16);
    const double back = sampled_distance(original, simplified, 16);
    // Float rounding of the stored vertices (coordinates up to ~2): far below eps.
    const double tolerance = 1e-5;
    std::printf("%s level %d: eps %g, %zu triangles, Hausdorff %g (level -> original) %g (original -> level)\n",
                lod_filter_name(filter), i, double(level.eps), level.triangles, there, back);
    EXPECT_LE(there, double(level.eps) + tolerance) << "level " << i;
    EXPECT_LE(back, double(level.eps) + tolerance) << "level " << i;
    EXPECT_FLOAT_EQ(level.range.r_min, options.k * level.eps);
  }
  // Ranges tile [0, r]: level 0 up to k eps_1, each level starts where the one before ends, the
  // last reaches r.
  EXPECT_EQ(lod->levels[0].range.r_min, 0.0f);
  for (std::size_t i = 1; i < lod->levels.size(); ++i) EXPECT_EQ(lod->levels[i].range.r_min, lod->levels[i - 1].range.r_max);
  // With an overlap, each level starts overlap * eps_i before the one below ends.
  LodOptions overlapping = options;
  overlapping.overlap = 1.0f;
  overlapping.levels = 1;
  auto shifted = build_lod(scene, radius, overlapping);
  ASSERT_TRUE(shifted);
  EXPECT_FLOAT_EQ(shifted->levels[1].range.r_min, shifted->levels[0].range.r_max - options.eps1);
  EXPECT_EQ(lod->levels.back().range.r_max, radius);
  // Sidedness survives simplification.
  for (std::size_t t = 0; t < lod->triangles.size(); ++t) ASSERT_EQ(lod->triangles.two_sided[t], scene.two_sided[0]);
}

TEST(RasterLod, EnvelopeLevelsStayWithinTheirEps) {
  expect_levels_within_eps(make_lod_scene(true), LodFilter::Envelope);
  expect_levels_within_eps(make_lod_scene(false), LodFilter::Envelope);
}

TEST(RasterLod, LevelsThatWouldStartBeyondTheRadiusAreNotBuilt) {
  LodOptions options;
  options.eps1 = 0.1f;
  options.levels = 5;
  auto lod = build_lod(make_lod_scene(true, 12), 1.0f, options);  // k eps_i < 1 for i = 1, 2 only
  ASSERT_TRUE(lod) << lod.error().message;
  ASSERT_EQ(lod->levels.size(), 3u);
  EXPECT_EQ(lod->levels.back().range.r_max, 1.0f);
}

TEST(RasterLod, InconsistentOneSidedComponentsStayAtFullDetail) {
  Scene s = make_lod_scene(false);
  const std::size_t sheet = 2 * 32 * 32;
  // Flip one triangle of the sheet: a one-sided surface that cannot be oriented without
  // changing which rays it blocks.
  std::swap(s.vertices[3 * 10 + 1], s.vertices[3 * 10 + 2]);
  LodOptions options;
  options.eps1 = 0.004f;
  auto lod = build_lod(s, 1.0f, options);
  ASSERT_TRUE(lod) << lod.error().message;
  EXPECT_EQ(lod->kept_components, 1u);
  EXPECT_EQ(lod->kept_triangles, sheet);
  ASSERT_EQ(lod->notes.size(), 1u);
  EXPECT_NE(lod->notes[0].find("1 of 2 components"), std::string::npos) << lod->notes[0];
  // The sheet's triangles reach r at level 0; the sphere's stop at k eps_1.
  EXPECT_EQ(lod->ranges[0].r_max, 1.0f);
  EXPECT_FLOAT_EQ(lod->ranges[sheet].r_max, 3.0f * 0.004f);
}

TEST(RasterLod, BadOptionsAreRefusedByName) {
  LodOptions o;
  o.eps1 = 0.0f;
  EXPECT_NE(check_lod_options(o).error().message.find("lod_eps1"), std::string::npos);
  o.eps1 = 1.0f;
  o.levels = 0;
  EXPECT_NE(check_lod_options(o).error().message.find("lod_levels"), std::string::npos);
  o.levels = 3;
  o.k = std::nanf("");
  EXPECT_NE(check_lod_options(o).error().message.find("lod_k"), std::string::npos);
  o.k = 3.0f;
  EXPECT_TRUE(check_lod_options(o));
  EXPECT_FALSE(build_lod(make_lod_scene(true, 4), -1.0f, o));
  EXPECT_FALSE(parse_lod_filter("quadric"));
}

// --- [0, a] and [a, r] give the mask of [0, r] -------------------------------------------------

lut::MaskEngine make_engine(int n, float radius, lut::MaskMode mode, Falloff falloff = Falloff::Constant) {
  auto pattern = make_sample_pattern(n, falloff);
  EXPECT_TRUE(pattern);
  auto rays = make_shadow_rays(*pattern, radius, 1e-4f);
  EXPECT_TRUE(rays);
  auto engine = lut::MaskEngine::build(*rays, mode);
  EXPECT_TRUE(engine) << engine.error().message;
  return std::move(*engine);
}

TEST(RasterLod, SplitRangeGivesTheSameMaskPerTriangle) {
  std::mt19937 rng(13);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  Scene s;
  for (int t = 0; t < 400; ++t) {
    const glm::vec3 c(u(rng), u(rng), u(rng));
    const float size = t % 2 ? 0.05f : 0.6f;
    s.add_triangle(c, c + size * glm::vec3(u(rng), u(rng), u(rng)), c + size * glm::vec3(u(rng), u(rng), u(rng)), t % 3 != 0, -1);
  }
  const lut::TriangleSet triangles = lut::TriangleSet::build(s);
  for (const lut::MaskMode mode : {lut::MaskMode::Lut, lut::MaskMode::Exact}) {
    for (const Falloff falloff : {Falloff::Constant, Falloff::Linear}) {
      const lut::MaskEngine engine = make_engine(128, 0.8f, mode, falloff);
      std::size_t blocked = 0, near = 0, far = 0;
      for (int k = 0; k < 300; ++k) {
        Receiver receiver;
        receiver.position = 0.8f * glm::vec3(u(rng), u(rng), u(rng));
        receiver.normal = glm::normalize(glm::vec3(u(rng), u(rng), u(rng)));
        receiver.key = static_cast<std::uint64_t>(k);
        const Frame frame = engine.rays().frame(receiver);
        for (std::uint32_t t = 0; t < triangles.size(); ++t) {
          const float a = 0.05f + 0.7f * float(t % 7) / 7.0f;
          const Mask<128> whole = engine.triangle_mask<128>(triangles, t, frame);
          const Mask<128> lower = range_mask<128>(engine, triangles, t, frame, {0.0f, a});
          const Mask<128> upper = range_mask<128>(engine, triangles, t, frame, {a, 0.8f});
          ASSERT_EQ(lower | upper, whole) << "triangle " << t << " receiver " << k;
          ASSERT_TRUE((lower & upper).none());
          // A middle range splits again the same way.
          const Mask<128> middle = range_mask<128>(engine, triangles, t, frame, {a, a + 0.1f});
          const Mask<128> top = range_mask<128>(engine, triangles, t, frame, {a + 0.1f, 0.8f});
          ASSERT_EQ(middle | top, upper);
          blocked += static_cast<std::size_t>(whole.popcount());
          near += static_cast<std::size_t>(lower.popcount());
          far += static_cast<std::size_t>(upper.popcount());
        }
      }
      EXPECT_GT(near, blocked / 20) << "the test must exercise both sides of the split";
      EXPECT_GT(far, blocked / 20);
    }
  }
}

TEST(RasterLod, SplitRangeGivesTheSameMasksThroughTheRasterPipeline) {
  // Every triangle twice: once with [0, a], once with [a, r]. The volumes of the first copy are
  // built with r_max = a, so a volume too small for its range would lose bits here.
  const Scene room = make_room();
  const float diagonal = room.bounds().diagonal();
  Scene doubled = room;
  doubled.vertices.insert(doubled.vertices.end(), room.vertices.begin(), room.vertices.end());
  doubled.two_sided.insert(doubled.two_sided.end(), room.two_sided.begin(), room.two_sided.end());
  doubled.material.insert(doubled.material.end(), room.material.begin(), room.material.end());
  const lut::TriangleSet plain = lut::TriangleSet::build(room);
  const lut::TriangleSet both = lut::TriangleSet::build(doubled);
  const Camera& camera = room.cameras.at(0);
  for (const lut::MaskMode mode : {lut::MaskMode::Lut, lut::MaskMode::Exact}) {
    const float r = 0.05f * diagonal;
    const lut::MaskEngine engine = make_engine(128, r, mode);
    const PixelReceivers pixels = raster_pixel_receivers(room, camera, 96, 72);
    const RasterResult reference = occlusion(pixels, room, plain, engine, camera);
    for (const float a : {0.1f * r, 0.45f * r}) {
      std::vector<DistanceRange> ranges(both.size());
      for (std::size_t t = 0; t < room.triangle_count(); ++t) {
        ranges[t] = {0.0f, a};
        ranges[t + room.triangle_count()] = {a, r};
      }
      RasterOptions options;
      options.ranges = ranges;
      const RasterResult split = occlusion(pixels, room, both, engine, camera, options);
      ASSERT_EQ(split.masks.size(), reference.masks.size());
      std::size_t differ = 0, blocked = 0;
      for (std::size_t i = 0; i < reference.masks.size(); ++i) {
        bool same = true;
        for (int w = 0; w < reference.masks.words(); ++w) same = same && reference.masks.row(i)[w] == split.masks.row(i)[w];
        differ += !same;
        blocked += static_cast<std::size_t>(reference.masks.blocked_count(i));
      }
      EXPECT_EQ(differ, 0u) << lut::mask_mode_name(mode) << " a = " << a;
      EXPECT_GT(blocked, reference.masks.size() * 128 / 500) << "too little occlusion to test";
      // The split volumes are smaller: the [0, a] copies draw fewer fragments than all of [0, r].
      EXPECT_LT(split.stats.masks, 2 * reference.stats.masks);
    }
  }
}

// --- The engine --------------------------------------------------------------------------------

engine::Options lod_engine_options(int samples) {
  engine::Options o;
  o.method = engine::Method::Raster;
  o.masks = lut::MaskMode::Exact;
  o.samples = samples;
  o.radius = engine::Length{1.0f, false};
  o.lod = LodOptions{};
  o.lod->eps1 = 0.02f;
  return o;
}

TEST(RasterLodEngine, LevelsAreBuiltOnceAndSharedByEveryEngineOfAGeometry) {
  const Scene scene = make_lod_scene(true, 16);
  const engine::Method methods[] = {engine::Method::Raster};
  Result<std::shared_ptr<const engine::Geometry>> geometry = engine::Geometry::build(scene, methods, {});
  ASSERT_TRUE(geometry) << geometry.error().message;
  const Camera camera = look_at({0.0f, 2.5f, -3.5f}, {0.0f, 0.3f, 0.0f}, 50.0f);
  Result<engine::Engine> first = engine::Engine::build(*geometry, lod_engine_options(64), engine::Receivers::Pixels);
  ASSERT_TRUE(first) << first.error().message;
  Result<PixelReceivers> pixels = first->render_pixels(camera, 48, 36);
  ASSERT_TRUE(pixels) << pixels.error().message;
  ASSERT_GT(pixels->receivers.size(), 100u);

  Result<std::optional<engine::LodLevels>> built = first->prepare_lod(*pixels, camera);
  ASSERT_TRUE(built && *built) << (built ? "off" : built.error().message);
  EXPECT_TRUE((*built)->built);
  EXPECT_GT((*built)->levels->triangles.size(), scene.triangle_count());  // level 0 and level 1
  // Again, and from another engine (other N) over the same geometry: the same levels, not rebuilt.
  Result<std::optional<engine::LodLevels>> again = first->prepare_lod(*pixels, camera);
  Result<engine::Engine> second = engine::Engine::build(*geometry, lod_engine_options(128), engine::Receivers::Pixels);
  ASSERT_TRUE(second) << second.error().message;
  Result<std::optional<engine::LodLevels>> other = second->prepare_lod(*pixels, camera);
  ASSERT_TRUE(again && *again && other && *other);
  EXPECT_FALSE((*again)->built);
  EXPECT_FALSE((*other)->built);
  EXPECT_EQ((*other)->levels, (*built)->levels);

  // The engine's masks are the raster backend's with the levels' triangles and ranges.
  Result<MaskSet> masks = first->pixel_masks(*pixels, camera);
  ASSERT_TRUE(masks) << masks.error().message;
  RasterOptions direct;
  direct.ranges = (*built)->levels->ranges;
  const RasterResult expected = occlusion(*pixels, *first->geometry().scene(), (*built)->levels->triangles,
                                          *first->mask_engine(), camera, direct);
  ASSERT_EQ(masks->size(), expected.masks.size());
  std::size_t differ = 0, blocked = 0;
  for (std::size_t i = 0; i < masks->size(); ++i) {
    differ += !std::equal(masks->row(i).begin(), masks->row(i).end(), expected.masks.row(i).begin());
    blocked += static_cast<std::size_t>(masks->blocked_count(i));
  }
  EXPECT_EQ(differ, 0u);
  EXPECT_GT(blocked, 0u) << "no occlusion to compare";
}

TEST(RasterLodEngine, OnlyTheRasterMethodTakesLevelsOfDetail) {
  const Scene scene = make_lod_scene(true, 8);
  engine::Options o = lod_engine_options(64);
  o.method = engine::Method::Bvh;
  Result<engine::Engine> bvh = engine::Engine::build(scene, o, engine::Receivers::Pixels);
  ASSERT_FALSE(bvh);
  EXPECT_EQ(bvh.error().message.rfind("lod:", 0), 0u) << bvh.error().message;
  o = lod_engine_options(64);
  o.lod->levels = 0;
  Result<void> checked = engine::check_options(o);
  ASSERT_FALSE(checked);
  EXPECT_EQ(checked.error().message.rfind("lod_levels:", 0), 0u) << checked.error().message;
  o.lod->levels = 1;
  o.lod->eps1 = 0.0f;  // auto
  EXPECT_TRUE(engine::check_options(o));
}

// --- The command line ------------------------------------------------------------------------

TEST(RasterLodCli, BadOptionsGetOneLine) {
  test::TempDir dir;
  const std::string out = " -W 16 -H 12 -o " + (dir / "a.exr").string() + " --png " + (dir / "a.png").string();
  expect_one_line_error(exao("render --method raster --lod fine" + out), "--lod");
  expect_one_line_error(exao("render --method raster --lod -0.5" + out), "--lod");
  expect_one_line_error(exao("render --method raster --lod 0" + out), "--lod");
  expect_one_line_error(exao("render --method raster --lod 1e9x" + out), "--lod");
  expect_one_line_error(exao("render --method raster --lod auto --lod-levels 0" + out), "--lod-levels");
  expect_one_line_error(exao("render --method raster --lod auto --lod-levels 9" + out), "--lod-levels");
  expect_one_line_error(exao("render --method raster --lod auto --lod-k 0" + out), "--lod-k");
  expect_one_line_error(exao("render --method raster --lod auto --lod-k nan" + out), "--lod-k");
  expect_one_line_error(exao("render --method raster --lod auto --lod-filter quadric" + out), "quadric");
  expect_one_line_error(exao("render --method bvh --lod auto" + out), "--lod");
  expect_one_line_error(exao("bench -W 16 -H 12 --methods raster --lod fine"), "--lod");
}

TEST(RasterLodCli, RenderSaysWhatAutoChose) {
  test::TempDir dir;
  const CommandResult run = exao("render --method raster --lod auto -W 32 -H 24 -o " + (dir / "a.exr").string() +
                                 " --png " + (dir / "a.png").string());
  EXPECT_EQ(run.status, 0) << run.output;
  EXPECT_NE(run.output.find("eps_1 = "), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("(auto)"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("raster+lod"), std::string::npos) << run.output;
}

}  // namespace
}  // namespace exao::raster
