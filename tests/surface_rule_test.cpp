// The surface rule (docs/surface-rule.md, core/surface_rule.h) and DESIGN.md section 8, test 3 on
// every kind of receiver: the exact orientation predicate against integer arithmetic; rays that
// start exactly in a tilted plane; the built-in `corners` scene with vertex receivers on every
// corner and edge; and the receivers bakes use on the real scenes (Conference's vertices,
// CesiumMilkTruck's vertices with the file's normals and its texels). Exact masks must equal
// Embree on every ray that does not graze (core/grazing.h).

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <iostream>
#include <string>
#include <vector>

#include "bake/bake.h"
#include "bake/document.h"
#include "bvh/bvh.h"
#include "bvh/occlusion.h"
#include "core/agreement.h"
#include "core/builtin_scenes.h"
#include "core/embree_reference.h"
#include "core/grazing.h"
#include "core/orientation.h"
#include "core/random.h"
#include "core/surface_rule.h"
#include "lut/brute.h"
#include "lut/mask_engine.h"
#include "lut/triangle_set.h"
#include "tests/test_support.h"

namespace exao {
namespace {

// --- The exact predicate ------------------------------------------------------------------------

// Floats that are multiples of 2^-18 below 2^20 in magnitude are integers k / 2^18 with |k| < 2^38:
// det(a - d, b - d, c - d) of such integers stays below 2^119 and is exact in __int128.
__extension__ typedef __int128 Int;  // GCC and Clang: exact products up to 2^127
Int scaled(float x) { return static_cast<Int>(static_cast<long long>(std::ldexp(static_cast<double>(x), 18))); }
int exact_sign(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c, const glm::vec3& d) {
  const Int ax = scaled(a.x) - scaled(d.x), ay = scaled(a.y) - scaled(d.y), az = scaled(a.z) - scaled(d.z);
  const Int bx = scaled(b.x) - scaled(d.x), by = scaled(b.y) - scaled(d.y), bz = scaled(b.z) - scaled(d.z);
  const Int cx = scaled(c.x) - scaled(d.x), cy = scaled(c.y) - scaled(d.y), cz = scaled(c.z) - scaled(d.z);
  const Int det = ax * (by * cz - bz * cy) - ay * (bx * cz - bz * cx) + az * (bx * cy - by * cx);
  return det > 0 ? 1 : det < 0 ? -1 : 0;
}

// A float on the 2^-bits grid (bits <= 18), from a uniform draw in [-range, range).
float grid_float(Rng& rng, float range, int bits = 18) {
  const double x = (2.0 * rng.uniform() - 1.0) * range;
  return static_cast<float>(std::ldexp(std::round(std::ldexp(x, bits)), -bits));
}

TEST(Orientation, MatchesIntegerArithmeticOnCoplanarAndNearlyCoplanarPoints) {
  Rng rng(12);
  int zeros = 0, nonzeros = 0;
  for (int i = 0; i < 40000; ++i) {
    // Ranges from 2^-6 to 2^19, so that coordinates of very different size meet.
    const float range = std::ldexp(1.0f, -6 + static_cast<int>(rng.uniform() * 26.0));
    const glm::vec3 a{grid_float(rng, range), grid_float(rng, range), grid_float(rng, range)};
    const glm::vec3 b{grid_float(rng, range), grid_float(rng, range), grid_float(rng, range)};
    const glm::vec3 c{grid_float(rng, range), grid_float(rng, range), grid_float(rng, range)};
    // d = a + s (b - a) + t (c - a) for small integers s, t: in the plane exactly when it is a
    // float; then one grid step off it, or not.
    const int s = static_cast<int>(rng.uniform() * 5.0) - 2, t = static_cast<int>(rng.uniform() * 5.0) - 2;
    const int nudge = static_cast<int>(rng.uniform() * 3.0) - 1;
    double exact[3];
    bool representable = true;
    for (int k = 0; k < 3; ++k) {
      exact[k] = double(a[k]) + double(s) * (double(b[k]) - double(a[k])) + double(t) * (double(c[k]) - double(a[k]));
      if (k == 1) exact[k] += double(nudge) * 0x1p-18;
      representable = representable && double(static_cast<float>(exact[k])) == exact[k] && std::abs(exact[k]) < 0x1p20;
    }
    if (!representable) continue;  // not a float, or off the integer range
    const glm::vec3 d(static_cast<float>(exact[0]), static_cast<float>(exact[1]), static_cast<float>(exact[2]));
    const int expected = exact_sign(a, b, c, d);
    ASSERT_EQ(orientation(a, b, c, d), expected)
        << i << std::hexfloat << ": a " << a.x << " " << a.y << " " << a.z << ", b " << b.x << " " << b.y << " " << b.z
        << ", c " << c.x << " " << c.y << " " << c.z << ", d " << d.x << " " << d.y << " " << d.z;
    (expected == 0 ? zeros : nonzeros)++;
  }
  // Axis-aligned and 45-degree planes: exactly coplanar by construction.
  for (int i = 0; i < 2000; ++i) {
    const float u = grid_float(rng, 1000.0f, 8), v = grid_float(rng, 1000.0f, 8), w = grid_float(rng, 1000.0f, 8);
    EXPECT_EQ(orientation({0, w, 0}, {1000, w, 0}, {0, w, 1000}, {u, w, v}), 0);
    EXPECT_EQ(orientation({0, 0, 0.75f}, {1, 0, 0.75f}, {0, 1, 1.75f}, {u, v, v + 0.75f}), 0);
    EXPECT_NE(orientation({0, 0, 0.75f}, {1, 0, 0.75f}, {0, 1, 1.75f}, {u, v, v + 0.75f + 0x1p-8f}), 0);
  }
  std::cout << zeros << " coplanar and " << nonzeros << " off-plane cases\n";
  EXPECT_GT(zeros, 2000) << "the test must meet exactly coplanar points";
  EXPECT_GT(nonzeros, 2000);
}

TEST(Orientation, SignFollowsTheFrontFace) {
  // cross(b - a, c - a) = +Y: a point above the face is on the side the normal points to (-1).
  const glm::vec3 a{0, 0, 0}, b{0, 0, 1}, c{1, 0, 0};
  EXPECT_EQ(orientation(a, b, c, {0.2f, 1e-30f, 0.2f}), -1);
  EXPECT_EQ(orientation(a, b, c, {0.2f, -1e-30f, 0.2f}), 1);
  EXPECT_EQ(orientation(a, b, c, {1e20f, 0.0f, -3e-20f}), 0);
}

TEST(SurfaceRule, OnPlaneMeansWithinSixteenUlpsOfTheCoordinates) {
  // The plane y = 0 through vertices of size 1; the origin at x = 7: the scale is 7.
  const glm::vec3 a{0, 0, 0}, b{0, 0, 1}, c{1, 0, 0};
  EXPECT_TRUE(origin_on_plane(a, b, c, {7.0f, 0.0f, 5.0f}));
  EXPECT_TRUE(origin_on_plane(a, b, c, {7.0f, 1e-30f, 5.0f}));
  EXPECT_TRUE(origin_on_plane(a, b, c, {7.0f, static_cast<float>(15.0 * 0x1p-24 * 7.0), 5.0f}));
  EXPECT_FALSE(origin_on_plane(a, b, c, {7.0f, static_cast<float>(17.0 * 0x1p-24 * 7.0), 5.0f}));
  EXPECT_FALSE(origin_on_plane(a, b, c, {7.0f, -1e-4f, 5.0f}));
  // A tilted plane through exactly representable points, and a sliver whose normal rounds.
  EXPECT_TRUE(origin_on_plane({0, 0, 0.75f}, {1, 0, 0.75f}, {0, 1, 1.75f}, {0.5f, 0.25f, 1.0f}));
  EXPECT_FALSE(origin_on_plane({0, 0, 0.75f}, {1, 0, 0.75f}, {0, 1, 1.75f}, {0.5f, 0.25f, 1.001f}));
  EXPECT_TRUE(origin_on_plane({0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {5, 6, 7})) << "degenerate: blocks nothing";
}

// --- Backends ----------------------------------------------------------------------------------

ShadowRays rays_for(int n, float radius, float offset) {
  auto pattern = make_sample_pattern(n, Falloff::Constant);
  EXPECT_TRUE(pattern);
  auto rays = make_shadow_rays(*pattern, radius, offset);
  EXPECT_TRUE(rays);
  return *rays;
}

// Exact masks (the brute backend: the definition) against Embree in the given ray mode.
Agreement exact_against_embree(const Scene& scene, const ShadowRays& rays, std::span<const Receiver> receivers,
                               EmbreeRays mode, bool use_bvh, const std::string& label, double min_blocked = 0.02) {
  auto embree = EmbreeScene::build(scene);
  EXPECT_TRUE(embree) << embree.error().message;
  EmbreeOptions options;
  options.rays = mode;
  const MaskSet reference = embree->occlusion(rays, receivers, options);
  auto engine = lut::MaskEngine::build(rays, lut::MaskMode::Exact);
  EXPECT_TRUE(engine);
  const lut::TriangleSet triangles = lut::TriangleSet::build(scene);
  MaskSet masks;
  if (use_bvh) {
    auto tree = bvh::Bvh::build(triangles);
    EXPECT_TRUE(tree);
    masks = bvh::occlusion(*tree, *engine, receivers);
  } else {
    masks = lut::brute_occlusion(*engine, triangles, receivers);
  }
  const GrazingTest grazing(scene, rays);
  const Agreement a = compare_masks(reference, masks, receivers, rays, &grazing);
  std::size_t blocked = 0;
  for (std::size_t r = 0; r < reference.size(); ++r) blocked += static_cast<std::size_t>(reference.blocked_count(r));
  std::cout << label << " (" << embree_rays_name(mode) << "): " << a.receivers << " receivers, " << a.rays_differ << " of "
            << a.rays << " rays differ (" << a.rays_differ_grazing << " grazing, largest closeness "
            << a.largest_closeness << " ulps), identical AO " << 100.0 * a.identical_share() << "%, "
            << a.receivers_grazing << " receivers differ only by grazing rays, " << a.ao_differ_not_grazing
            << " otherwise; " << blocked << " rays blocked\n";
  // Name the rays that break the rule, so that a failure says where to look.
  if (a.rays_differ_not_grazing() > 0) {
    int shown = 0;
    for (std::size_t r = 0; r < reference.size() && shown < 8; ++r) {
      for (int i = 0; i < rays.count() && shown < 8; ++i) {
        if (reference.blocked(r, i) == masks.blocked(r, i)) continue;
        const double c = grazing.closeness(rays.frame(receivers[r]), i);
        if (c <= kGrazingUlps) continue;
        const glm::vec3 p = receivers[r].position, n = receivers[r].normal;
        std::cout << "  receiver " << r << " at (" << p.x << ", " << p.y << ", " << p.z << ") normal (" << n.x << ", "
                  << n.y << ", " << n.z << ") ray " << i << ": embree " << reference.blocked(r, i) << ", masks "
                  << masks.blocked(r, i) << ", closeness " << c << " ulps\n";
        ++shown;
      }
    }
  }
  EXPECT_GE(double(blocked), min_blocked * double(a.rays)) << label << ": too little occlusion to test anything";
  return a;
}

void expect_equal_but_grazing(const Agreement& a, const std::string& label) {
  EXPECT_EQ(a.rays_differ_not_grazing(), 0u) << label;
  EXPECT_EQ(a.ao_differ_not_grazing, 0u) << label;
  EXPECT_GE(a.ray_share(), 0.9999) << label;
}

// Receivers `x y z nx ny nz` on a two-sided triangle of the plane x + y + z = 0 (integer
// vertices, exactly representable), with normals in the plane, kept only where the frame's
// origin p' lies in the plane exactly: about half the rays go through the plane at t = 0.
TEST(SurfaceRule, RaysFromATiltedPlaneAreNotBlockedByIt) {
  Scene scene;
  ASSERT_TRUE(scene.add_triangle({100, -100, 0}, {0, 100, -100}, {-100, 0, 100}, true, 0));
  const ShadowRays rays = rays_for(128, 1.0f, 1e-3f);
  Rng rng(3);
  std::vector<Receiver> receivers;
  for (int i = 0; receivers.size() < 200 && i < 20000; ++i) {
    const float x = static_cast<float>(rng.uniform() * 20.0 - 10.0), y = static_cast<float>(rng.uniform() * 20.0 - 10.0);
    const Receiver receiver{{x, y, -(x + y)}, glm::normalize(glm::vec3(1.0f, -1.0f, 0.0f)), static_cast<std::uint64_t>(i)};
    if (origin_on_plane(scene.triangle(0)[0], scene.triangle(0)[1], scene.triangle(0)[2], rays.frame(receiver).origin)) {
      receivers.push_back(receiver);
    }
  }
  ASSERT_EQ(receivers.size(), 200u);
  for (const EmbreeRays mode : {EmbreeRays::Single, EmbreeRays::Packet16}) {
    auto embree = EmbreeScene::build(scene);
    ASSERT_TRUE(embree);
    EmbreeOptions options;
    options.rays = mode;
    const MaskSet reference = embree->occlusion(rays, receivers, options);
    auto engine = lut::MaskEngine::build(rays, lut::MaskMode::Exact);
    ASSERT_TRUE(engine);
    const MaskSet masks = lut::brute_occlusion(*engine, lut::TriangleSet::build(scene), receivers);
    for (std::size_t r = 0; r < receivers.size(); ++r) {
      EXPECT_EQ(reference.blocked_count(r), 0) << "embree " << embree_rays_name(mode) << ", receiver " << r;
      EXPECT_EQ(masks.blocked_count(r), 0) << "masks, receiver " << r;
    }
  }
  // The same receivers lifted off the plane (by 4e-4, 60 times the tolerance at the vertices'
  // scale of 100) are blocked on a good share of their rays:
  // the rule is about the start only.
  std::vector<Receiver> lifted = receivers;
  for (Receiver& r : lifted) r.normal = glm::normalize(glm::vec3(1.0f, -1.0f, 0.0f) + glm::vec3(0.3f));
  auto embree = EmbreeScene::build(scene);
  ASSERT_TRUE(embree);
  const MaskSet masks = embree->occlusion(rays, lifted);
  for (std::size_t r = 0; r < lifted.size(); ++r) EXPECT_GT(masks.blocked_count(r), 25) << r;
}

// The bake's receivers of a document, as the bake asks the engine about them.
std::vector<Receiver> receivers_of(bake::Document& document, const bake::BakeOptions& options) {
  auto receivers = bake::bake_receivers(document, options);
  EXPECT_TRUE(receivers) << receivers.error().message;
  return receivers ? *receivers : std::vector<Receiver>{};
}

TEST(SurfaceRule, CornersVertexReceiversEqualEmbree) {
  for (const bool two_sided : {false, true}) {
    Scene scene = make_corners();
    if (two_sided) apply_sidedness(scene, Sidedness::Two);
    auto document = bake::Document::from_scene(scene);
    ASSERT_TRUE(document) << document.error().message;
    const std::vector<Receiver> receivers = receivers_of(*document, {});
    ASSERT_GT(receivers.size(), 500u);
    const float diagonal = scene.bounds().diagonal();
    // Count the receivers whose p' lies exactly in the plane of a triangle in reach: the rule's
    // case must be common here, or the scene tests nothing.
    for (const float offset : {kDefaultOffsetFraction * diagonal, 0.0f}) {
      for (const float radius : {0.05f * diagonal, 0.01f * diagonal}) {
        const ShadowRays rays = rays_for(128, radius, offset);
        std::size_t on_plane = 0;
        for (const Receiver& receiver : receivers) {
          const glm::vec3 o = rays.frame(receiver).origin;
          for (std::size_t t = 0; t < scene.triangle_count(); ++t) {
            const auto tri = scene.triangle(t);
            // In reach: the cells are 0.25 wide, so a triangle's points are within 0.36 of its centroid.
            const glm::vec3 centroid = (tri[0] + tri[1] + tri[2]) / 3.0f;
            if (glm::length(centroid - o) < radius + 0.36f && origin_on_plane(tri[0], tri[1], tri[2], o)) {
              ++on_plane;
              break;
            }
          }
        }
        std::cout << on_plane << " of " << receivers.size() << " receivers start in the plane of a triangle in reach\n";
        EXPECT_GE(on_plane, offset == 0.0f ? receivers.size() : std::size_t{10});
        const std::string label = std::string("corners ") + (two_sided ? "two-sided" : "one-sided") +
                                  " offset " + std::to_string(offset) + " r " + std::to_string(radius);
        for (const EmbreeRays mode : {EmbreeRays::Single, EmbreeRays::Packet16}) {
          // At offset 0 every ray starts on its own surface and, by the rule, passes its neighbours.
          const Agreement a = exact_against_embree(scene, rays, receivers, mode, false, label, offset == 0.0f ? 0.0 : 0.02);
          expect_equal_but_grazing(a, label);
        }
      }
    }
  }
}

// --- The real scenes ----------------------------------------------------------------------------

// `stride` > 1 keeps every stride-th receiver, to keep a large set's test short.
void check_bake_receivers(const std::string& relative, const bake::BakeOptions& options, float radius_fraction,
                          const std::string& label, std::size_t stride = 1) {
  const auto path = test::real_scene(relative);
  EXAO_REQUIRE_SCENE(path);
  bake::ConvertOptions convert;
  if (options.target == bake::Target::Texture) {
    convert.atlas_size = options.texture_size;
    convert.atlas_padding = 2 * options.margin + 2;
  }
  auto document = bake::Document::open(path.string(), convert);
  ASSERT_TRUE(document) << document.error().message;
  std::vector<Receiver> receivers = receivers_of(*document, options);
  for (std::size_t i = 0; i * stride < receivers.size(); ++i) receivers[i] = receivers[i * stride];
  receivers.resize((receivers.size() + stride - 1) / stride);
  ASSERT_GT(receivers.size(), 1000u);
  const Scene& scene = document->scene();
  const float diagonal = scene.bounds().diagonal();
  const ShadowRays rays = rays_for(128, radius_fraction * diagonal, kDefaultOffsetFraction * diagonal);
  const Agreement a = exact_against_embree(scene, rays, receivers, EmbreeRays::Packet16, true, label);
  ::testing::Test::RecordProperty(label + " rays differing", std::to_string(a.rays_differ));
  ::testing::Test::RecordProperty(label + " receivers differing only by grazing rays", std::to_string(a.receivers_grazing));
  expect_equal_but_grazing(a, label);
}

TEST(SurfaceRule, ConferenceVertexReceiversEqualEmbree) {
  // Every third of the 152,571 vertices (exao bake --masks exact --compare embree checks them all).
  check_bake_receivers("Conference/conference.obj", {}, 0.01f, "Conference vertices, area-weighted normals, r 1%", 3);
}

TEST(SurfaceRule, TruckVertexReceiversWithFileNormalsEqualEmbree) {
  bake::BakeOptions options;
  options.normals = bake::NormalSource::File;
  check_bake_receivers("CesiumMilkTruck/glTF/CesiumMilkTruck.gltf", options, 0.05f,
                       "CesiumMilkTruck vertices, file normals, r 5%");
}

TEST(SurfaceRule, TruckTexelReceiversEqualEmbree) {
  bake::BakeOptions options;
  options.target = bake::Target::Texture;
  // 256^2 with 4 receivers per texel: 300k receivers, a quarter of the 512^2 map (exao bake
  // --texture 512 --masks exact --compare embree measures that one), to keep the test short.
  options.texture_size = 256;
  check_bake_receivers("CesiumMilkTruck/glTF/CesiumMilkTruck.gltf", options, 0.05f, "CesiumMilkTruck texels 256, r 5%");
}

}  // namespace
}  // namespace exao

