// DESIGN.md section 8.6: every equality holds on every instruction set the machine runs, bit for
// bit. The masks of brute at the scalar level are the reference; bvh, brute and raster at every
// level this CPU runs (core/isa.h) must reproduce them, on the room and on Conference.

#include <gtest/gtest.h>

#include <algorithm>
#include <iostream>

#include "bvh/occlusion.h"
#include "core/builtin_scenes.h"
#include "core/embree_reference.h"
#include "core/isa.h"
#include "io/polygon_soup_loader.h"
#include "core/pixel_receivers.h"
#include "lut/brute.h"
#include "raster/occlusion.h"
#include "tests/test_support.h"

namespace exao {
namespace {

std::size_t differing_rows(const MaskSet& a, const MaskSet& b) {
  std::size_t n = 0;
  for (std::size_t i = 0; i < a.size(); ++i) n += !std::equal(a.row(i).begin(), a.row(i).end(), b.row(i).begin());
  return n;
}

void expect_every_isa_equal(const Scene& scene, const Camera& camera, int width, int height, int samples,
                            lut::MaskMode mode) {
  SCOPED_TRACE(scene.name + " N=" + std::to_string(samples) + " " + lut::mask_mode_name(mode));
  const float diagonal = scene.bounds().diagonal();
  Result<SamplePattern> pattern = make_sample_pattern(samples, Falloff::Constant);
  ASSERT_TRUE(pattern);
  Result<ShadowRays> rays = make_shadow_rays(*pattern, 0.03f * diagonal, 1e-4f * diagonal);
  ASSERT_TRUE(rays);
  Result<EmbreeScene> embree = EmbreeScene::build(scene);
  ASSERT_TRUE(embree);
  const PixelReceivers pixels = pixel_receivers(*embree, scene, camera, width, height);
  ASSERT_GT(pixels.receivers.size(), 100u);
  const lut::TriangleSet triangles = lut::TriangleSet::build(scene);
  Result<bvh::Bvh> tree = bvh::Bvh::build(triangles);
  ASSERT_TRUE(tree);

  Result<lut::MaskEngine> scalar = lut::MaskEngine::build(*rays, mode, 0, Isa::Scalar);
  ASSERT_TRUE(scalar);
  const MaskSet reference = lut::brute_occlusion(*scalar, triangles, pixels.receivers);
  std::size_t occluded = 0;
  for (std::size_t i = 0; i < reference.size(); ++i) occluded += reference.blocked_count(i) > 0;
  EXPECT_GT(occluded, reference.size() / 10);

  for (const Isa isa : supported_isas()) {
    SCOPED_TRACE(isa_name(isa));
    Result<lut::MaskEngine> engine = lut::MaskEngine::build(*rays, mode, 0, isa);
    ASSERT_TRUE(engine);
    EXPECT_EQ(differing_rows(bvh::occlusion(*tree, *engine, pixels.receivers), reference), 0u);
    EXPECT_EQ(differing_rows(lut::brute_occlusion(*engine, triangles, pixels.receivers), reference), 0u);
    const raster::RasterResult raster =
        raster::occlusion(pixels, scene, triangles, *engine, camera, raster::RasterOptions{}, {});
    EXPECT_EQ(differing_rows(raster.masks, reference), 0u);
  }
}

TEST(IsaEquality, RoomOnEveryInstructionSet) {
  std::cout << "instruction sets:";
  for (const Isa isa : supported_isas()) std::cout << ' ' << isa_name(isa);
  std::cout << '\n';
  const Scene room = make_room();
  for (const int n : {128, 1024}) {
    for (const lut::MaskMode mode : {lut::MaskMode::Exact, lut::MaskMode::Lut}) {
      expect_every_isa_equal(room, room.cameras[0], 96, 72, n, mode);
    }
  }
}

TEST(IsaEquality, ConferenceOnEveryInstructionSet) {
  const auto path = test::real_scene("Conference/conference.obj");
  EXAO_REQUIRE_SCENE(path);
  Result<Scene> scene = load_polygon_soup(path.string());
  ASSERT_TRUE(scene) << scene.error().message;
  const Camera camera = look_at({-900.0f, 450.0f, -900.0f}, {1000.0f, 150.0f, 400.0f}, 60.0f);
  expect_every_isa_equal(*scene, camera, 64, 48, 128, lut::MaskMode::Exact);
}

}  // namespace
}  // namespace exao
