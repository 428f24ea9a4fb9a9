// DESIGN.md section 8.1: the BVH backend equals brute bit for bit, for every receiver, whatever
// the culling and ordering do.

#include <gtest/gtest.h>

#include <tuple>

#include "bvh/occlusion.h"
#include "core/builtin_scenes.h"
#include "core/embree_reference.h"
#include "io/polygon_soup_loader.h"
#include "core/pixel_receivers.h"
#include "core/random.h"
#include "lut/brute.h"
#include "tests/test_support.h"

namespace exao {
namespace {

struct Case {
  std::string name;
  Scene scene;
  Camera camera;
  int width, height;
};

// Pixel receivers (what a renderer asks for) plus receivers on random triangles, facing either
// way (what a bake or a bounce asks for).
std::vector<Receiver> receivers_for(const Case& c) {
  Result<EmbreeScene> embree = EmbreeScene::build(c.scene);
  EXPECT_TRUE(embree.has_value());
  std::vector<Receiver> out = pixel_receivers(*embree, c.scene, c.camera, c.width, c.height).receivers;
  Rng rng(3);
  for (int i = 0; i < 200; ++i) {
    const auto t = rng.below(static_cast<std::uint32_t>(c.scene.triangle_count()));
    const auto tri = c.scene.triangle(t);
    const float u = static_cast<float>(rng.uniform()), v = static_cast<float>(rng.uniform());
    const float a = std::min(u, v), b = std::max(u, v) - a;
    glm::vec3 n = glm::cross(tri[1] - tri[0], tri[2] - tri[0]);
    if (rng.below(2)) n = -n;
    out.push_back({tri[0] + a * (tri[1] - tri[0]) + b * (tri[2] - tri[0]), n, 1000000u + static_cast<std::uint64_t>(i)});
  }
  return out;
}

void expect_bvh_equals_brute(const Case& c, int samples, Falloff falloff, lut::MaskMode mode,
                             const bvh::BvhOptions& bvh_options = {}) {
  SCOPED_TRACE(c.name + " N=" + std::to_string(samples) + " " + falloff_name(falloff) + " " + lut::mask_mode_name(mode) +
               " branching " + std::to_string(bvh_options.branching));
  const float diagonal = c.scene.bounds().diagonal();
  Result<SamplePattern> pattern = make_sample_pattern(samples, falloff);
  ASSERT_TRUE(pattern.has_value());
  Result<ShadowRays> rays = make_shadow_rays(*pattern, 0.05f * diagonal, 1e-4f * diagonal);
  ASSERT_TRUE(rays.has_value());
  Result<lut::MaskEngine> engine = lut::MaskEngine::build(*rays, mode);
  ASSERT_TRUE(engine.has_value()) << engine.error().message;
  const lut::TriangleSet triangles = lut::TriangleSet::build(c.scene);
  Result<bvh::Bvh> tree = bvh::Bvh::build(triangles, bvh_options);
  ASSERT_TRUE(tree.has_value()) << tree.error().message;

  const std::vector<Receiver> receivers = receivers_for(c);
  const MaskSet expected = lut::brute_occlusion(*engine, triangles, receivers);
  bvh::TraversalStats stats;
  const MaskSet got = bvh::occlusion(*tree, *engine, receivers, {}, &stats);
  ASSERT_EQ(got.size(), expected.size());
  std::size_t differing = 0, occluded = 0;
  for (std::size_t i = 0; i < receivers.size(); ++i) {
    occluded += expected.blocked_count(i) > 0;
    if (!std::equal(got.row(i).begin(), got.row(i).end(), expected.row(i).begin())) {
      if (differing++ < 5) ADD_FAILURE() << "receiver " << i << ": bvh blocks " << got.blocked_count(i) << ", brute " << expected.blocked_count(i);
    }
  }
  EXPECT_EQ(differing, 0u);
  EXPECT_GT(occluded, receivers.size() / 10) << "the scene should occlude a fair share of receivers";
  EXPECT_EQ(stats.receivers, receivers.size());
  // Exact masks skip the clip of step 7 (lut/kernels-inl.h): it must remove nothing they set.
  if (mode == lut::MaskMode::Exact) {
    EXPECT_EQ(stats.kernels.clip_removed, 0u) << "bits outside their clip spheres";
  }
}

Case room_case() {
  Scene scene = make_room();
  const Camera camera = scene.cameras[0];
  return {"room", std::move(scene), camera, 48, 36};
}

TEST(Bvh, EqualsBruteOnRoom) {
  const Case one_sided = room_case();
  Case two_sided = room_case();
  two_sided.name = "room two-sided";
  apply_sidedness(two_sided.scene, Sidedness::Two);
  for (const Case* c : std::initializer_list<const Case*>{&one_sided, &two_sided})
    for (const int n : {128, 1024})
      for (const Falloff f : {Falloff::Constant, Falloff::Linear})
        for (const lut::MaskMode mode : {lut::MaskMode::Lut, lut::MaskMode::Exact}) expect_bvh_equals_brute(*c, n, f, mode);
}

// The box cull of the children (bvh/traverse-inl.h) is as tight as it may be: a box shrunk by a
// thousandth of the scene drops rays that its triangles block.
TEST(Bvh, ATooTightBoxCullIsCaught) {
  const Case c = room_case();
  const float diagonal = c.scene.bounds().diagonal();
  Result<SamplePattern> pattern = make_sample_pattern(128, Falloff::Constant);
  ASSERT_TRUE(pattern.has_value());
  Result<ShadowRays> rays = make_shadow_rays(*pattern, 0.05f * diagonal, 1e-4f * diagonal);
  ASSERT_TRUE(rays.has_value());
  Result<lut::MaskEngine> engine = lut::MaskEngine::build(*rays, lut::MaskMode::Exact);
  ASSERT_TRUE(engine.has_value());
  const lut::TriangleSet triangles = lut::TriangleSet::build(c.scene);
  Result<bvh::Bvh> tree = bvh::Bvh::build(triangles, {});
  ASSERT_TRUE(tree.has_value());
  const std::vector<Receiver> receivers = receivers_for(c);
  const MaskSet expected = lut::brute_occlusion(*engine, triangles, receivers);
  const auto differing = [&] {
    const MaskSet got = bvh::occlusion(*tree, *engine, receivers);
    std::size_t n = 0;
    for (std::size_t i = 0; i < receivers.size(); ++i) {
      n += !std::equal(got.row(i).begin(), got.row(i).end(), expected.row(i).begin());
    }
    return n;
  };
  EXPECT_EQ(differing(), 0u);
  tree->box_shrink_for_test = 1e-3f * diagonal;
  EXPECT_GT(differing(), receivers.size() / 100) << "a box cull too tight by 1e-3 of the scene went unnoticed";
}

TEST(Bvh, EqualsBruteWithEveryBranchingAndLeafSize) {
  const Case c = room_case();
  for (const int branching : {2, 4})
    for (const int leaf : {1, 3, 8}) expect_bvh_equals_brute(c, 128, Falloff::Constant, lut::MaskMode::Lut, {branching, leaf});
}

TEST(Bvh, EqualsBruteOnConference) {
  const auto path = test::real_scene("Conference/conference.obj");
  EXAO_REQUIRE_SCENE(path);
  Result<Scene> loaded = load_polygon_soup(path.string());
  ASSERT_TRUE(loaded.has_value()) << loaded.error().message;
  const Camera camera = look_at({-900.0f, 350.0f, -950.0f}, {600.0f, 150.0f, 300.0f}, 70.0f);
  Case two_sided{"conference", std::move(*loaded), camera, 24, 18};  // OBJ: two-sided
  Case one_sided = two_sided;
  one_sided.name = "conference one-sided";
  apply_sidedness(one_sided.scene, Sidedness::One);
  for (const Case* c : std::initializer_list<const Case*>{&two_sided, &one_sided})
    for (const int n : {128, 1024})
      for (const Falloff f : {Falloff::Constant, Falloff::Linear})
        for (const lut::MaskMode mode : {lut::MaskMode::Lut, lut::MaskMode::Exact}) expect_bvh_equals_brute(*c, n, f, mode);
}

TEST(Bvh, SingleTriangleScene) {
  Scene scene;
  scene.add_triangle({-1, 1, -1}, {1, 1, -1}, {0, 1, 1}, false, 0);  // front face down, toward the receiver
  Case c{"one triangle", scene, look_at({0, 3, 3}, {0, 0, 0}, 60), 16, 12};
  // The floor receivers come from random points on the triangle itself; add one under it.
  Result<SamplePattern> pattern = make_sample_pattern(64, Falloff::Constant);
  ASSERT_TRUE(pattern.has_value());
  Result<ShadowRays> rays = make_shadow_rays(*pattern, 2.0f, 0.0f);
  ASSERT_TRUE(rays.has_value());
  Result<lut::MaskEngine> engine = lut::MaskEngine::build(*rays, lut::MaskMode::Exact);
  ASSERT_TRUE(engine.has_value());
  const lut::TriangleSet triangles = lut::TriangleSet::build(scene);
  Result<bvh::Bvh> tree = bvh::Bvh::build(triangles);
  ASSERT_TRUE(tree.has_value());
  const Receiver below{{0, 0, 0}, {0, 1, 0}, 1};
  const MaskSet masks = bvh::occlusion(*tree, *engine, std::span(&below, 1));
  EXPECT_GT(masks.blocked_count(0), 0);
  EXPECT_EQ(masks.bits(), lut::brute_occlusion(*engine, triangles, std::span(&below, 1)).bits());
}

// The node spheres are their definition (bvh.cpp set_sphere): centred on the box, radius the
// farthest reach |c - centre| + r of a triangle sphere below, in doubles, rounded up. The build
// finds that maximum by pruning subtrees with their own spheres; here every triangle below is
// visited. The nodes are laid out depth first, a subtree's nodes together.
struct SphereCheck {
  const bvh::Bvh& tree;
  std::size_t slots = 0;

  // Appends the triangle spheres below slot k of node `index` to `out` (as centre, radius).
  void gather(std::uint32_t index, int k, std::vector<glm::vec4>& out) const {
    const bvh::Node& node = tree.nodes[index];
    if (node.leaf_size[k] != 0) {
      const bvh::LeafBlock leaf = tree.leaf_at(node.child[k]);
      for (int l = 0; l < static_cast<int>(leaf.count); ++l)
        out.emplace_back(leaf.cx()[l], leaf.cy()[l], leaf.cz()[l], leaf.radius()[l]);
      return;
    }
    for (int j = 0; j < tree.nodes[node.child[k]].child_count; ++j) gather(node.child[k], j, out);
  }

  // Checks the subtree of node `index`, placed at `index`; returns its node count.
  std::uint32_t check(std::uint32_t index) {
    const bvh::Node& node = tree.nodes[index];
    std::uint32_t next = index + 1;
    for (int k = 0; k < node.child_count; ++k) {
      std::vector<glm::vec4> spheres;
      gather(index, k, spheres);
      const glm::vec3 centre_f(0.5f * (node.lo_x[k] + node.hi_x[k]), 0.5f * (node.lo_y[k] + node.hi_y[k]),
                               0.5f * (node.lo_z[k] + node.hi_z[k]));
      double reach = 0.0;
      for (const glm::vec4& s : spheres) {
        reach = std::max(reach, glm::length(glm::dvec3(s.x, s.y, s.z) - glm::dvec3(centre_f)) + double(s.w));
      }
      const float radius = std::nextafter(static_cast<float>(reach * (1.0 + 1e-6)), INFINITY);
      EXPECT_EQ(node.centre_x[k], centre_f.x);
      EXPECT_EQ(node.centre_y[k], centre_f.y);
      EXPECT_EQ(node.centre_z[k], centre_f.z);
      EXPECT_EQ(node.radius[k], radius) << "node " << index << " slot " << k << " of " << spheres.size() << " triangles";
      ++slots;
      if (node.leaf_size[k] != 0) continue;
      EXPECT_EQ(node.child[k], next) << "node " << index << " slot " << k << ": not depth first";
      next += check(node.child[k]);
    }
    return next - index;
  }
};

void expect_spheres_are_their_definition(const Scene& scene, const std::string& name) {
  SCOPED_TRACE(name);
  for (const int branching : {2, 4}) {
    Result<bvh::Bvh> tree = bvh::Bvh::build(scene, {branching, 8});
    ASSERT_TRUE(tree.has_value()) << tree.error().message;
    SphereCheck check{*tree};
    EXPECT_EQ(check.check(0), tree->nodes.size());
    EXPECT_GE(check.slots, tree->nodes.size());
  }
}

TEST(Bvh, NodeSpheresAreTheirDefinition) {
  expect_spheres_are_their_definition(make_room(), "room");
  // Far from the origin the doubles' rounding is largest next to the spheres' own sizes.
  Scene far = make_room();
  for (glm::vec3& v : far.vertices) v = v * 1e-3f + glm::vec3(3e4f, -7e4f, 1e5f);
  expect_spheres_are_their_definition(far, "room, small and far");
}

TEST(Bvh, NodeSpheresAreTheirDefinitionOnConference) {
  const auto path = test::real_scene("Conference/conference.obj");
  EXAO_REQUIRE_SCENE(path);
  Result<Scene> loaded = load_polygon_soup(path.string());
  ASSERT_TRUE(loaded.has_value()) << loaded.error().message;
  expect_spheres_are_their_definition(*loaded, "conference");
}

}  // namespace
}  // namespace exao
