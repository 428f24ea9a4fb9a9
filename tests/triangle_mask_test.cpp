// Triangle masks and region masks: against ray casting in double, against their scalar twins,
// and the conservativeness the BVH relies on (a sphere's mask holds every ray that can hit it;
// a node's mask holds every mask of the triangles inside it).

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <optional>

#include "core/random.h"
#include "core/receiver_frame.h"
#include "core/shadow_rays.h"
#include "bvh/bvh.h"
#include "bvh/traverse.h"
#include "lut/mask_engine.h"

namespace exao::lut {
namespace {

ShadowRays rays_of(int n, Falloff falloff, float radius = 1.0f) {
  auto pattern = make_sample_pattern(n, falloff);
  EXPECT_TRUE(pattern);
  auto rays = make_shadow_rays(*pattern, radius, 0.0f);
  EXPECT_TRUE(rays);
  return *rays;
}

MaskEngine engine_of(const ShadowRays& rays, MaskMode mode, int resolution = 0) {
  auto engine = MaskEngine::build(rays, mode, resolution);
  EXPECT_TRUE(engine) << engine.error().message;
  return std::move(*engine);
}

glm::dvec3 random_in_box(Rng& rng, glm::dvec3 lo, glm::dvec3 hi) {
  return lo + glm::dvec3(rng.uniform(), rng.uniform(), rng.uniform()) * (hi - lo);
}

glm::dvec3 random_unit(Rng& rng) {
  for (;;) {
    const glm::dvec3 v = random_in_box(rng, glm::dvec3(-1.0), glm::dvec3(1.0));
    const double l = glm::length(v);
    if (l > 0.1 && l <= 1.0) return v / l;
  }
}

// A receiver frame somewhere in a world of coordinates up to `spread`.
Frame random_frame(Rng& rng, const ShadowRays& rays, float spread) {
  Receiver receiver;
  receiver.position = glm::vec3(random_in_box(rng, glm::dvec3(-spread), glm::dvec3(spread)));
  receiver.normal = glm::vec3(random_unit(rng));
  receiver.key = rng.next();
  return rays.frame(receiver);
}

glm::dvec3 local_to_world(const Frame& f, const glm::dvec3& local) {
  return glm::dvec3(f.origin) + local.x * glm::dvec3(f.tangent) + local.y * glm::dvec3(f.bitangent) +
         local.z * glm::dvec3(f.normal);
}
glm::dvec3 world_to_local(const Frame& f, const glm::dvec3& world) {
  const glm::dvec3 d = world - glm::dvec3(f.origin);
  return {glm::dot(d, glm::dvec3(f.tangent)), glm::dot(d, glm::dvec3(f.bitangent)), glm::dot(d, glm::dvec3(f.normal))};
}

// A set of one triangle, given in the frame's local coordinates (units of r), stored in world.
TriangleSet one_triangle(const Frame& frame, float r, glm::dvec3 a, glm::dvec3 b, glm::dvec3 c, bool two_sided) {
  Scene scene;
  scene.add_triangle(glm::vec3(local_to_world(frame, a * double(r))), glm::vec3(local_to_world(frame, b * double(r))),
                     glm::vec3(local_to_world(frame, c * double(r))), two_sided, 0);
  return TriangleSet::build(scene);
}

// Does the segment from the origin to l * w meet the triangle (local, double)? One-sided
// triangles only from the front (the ray travels against the CCW normal). Moller-Trumbore.
bool segment_hits(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, bool two_sided,
                  const glm::dvec3& w, double l) {
  const glm::dvec3 e1 = b - a, e2 = c - a;
  const glm::dvec3 n = glm::cross(e1, e2);
  if (!two_sided && !(glm::dot(w, n) < 0.0)) return false;
  const glm::dvec3 p = glm::cross(w, e2);
  const double det = glm::dot(e1, p);
  if (det == 0.0) return false;
  const glm::dvec3 s = -a;
  const double u = glm::dot(s, p) / det;
  const glm::dvec3 q = glm::cross(s, e1);
  const double v = glm::dot(w, q) / det;
  const double t = glm::dot(e2, q) / det;
  return u >= 0.0 && v >= 0.0 && u + v <= 1.0 && t >= 0.0 && t <= l;
}

// Does the segment from the origin to l * w (local, double) meet the ball (c, radius)?
bool segment_meets_ball(const glm::dvec3& c, double radius, const glm::dvec3& w, double l) {
  if (glm::dot(c, c) <= radius * radius) return true;
  const double t = std::clamp(glm::dot(w, c), 0.0, l);  // nearest point of the segment to c
  const glm::dvec3 q = t * w - c;
  return glm::dot(q, q) <= radius * radius;
}

TEST(RegionMask, HoldsEveryRayThatHitsTheSphere) {
  std::size_t hits = 0, extra = 0, spheres = 0;
  for (const Falloff falloff : {Falloff::Constant, Falloff::Linear}) {
    const ShadowRays rays = rays_of(256, falloff, 2.5f);
    const MaskEngine engine = engine_of(rays, MaskMode::Exact);
    const double r = rays.radius;
    Rng rng(99);
    for (int trial = 0; trial < 20000; ++trial) {
      // Radii from 1e-4 r (narrow cones far away) to 2 r, centres anywhere within reach, and
      // every tenth sphere with the origin within a hair of its surface.
      const double radius = r * std::pow(10.0, -4.0 + 4.3 * rng.uniform());
      glm::dvec3 c = random_in_box(rng, glm::dvec3(-1.5 * r), glm::dvec3(1.5 * r));
      if (trial % 10 == 0) c = random_unit(rng) * radius * (1.0 + 1e-6 * (rng.uniform() - 0.3));
      const glm::vec3 cf(c);
      const float radius_f = static_cast<float>(radius);
      const Mask<256> mask = engine.region_mask<256>(cf, radius_f, kTriangleMargin);
      ++spheres;
      for (int i = 0; i < rays.count(); ++i) {
        const bool hit = segment_meets_ball(glm::dvec3(cf), radius_f, glm::dvec3(rays.pattern.directions[i]),
                                            double(rays.pattern.lengths[i]) * r);
        if (hit) {
          ++hits;
          ASSERT_TRUE(mask.test(i)) << "trial " << trial << " ray " << i << " centre " << c.x << ' ' << c.y << ' '
                                    << c.z << " radius " << radius;
        } else if (mask.test(i) && trial % 10 != 0) {
          ++extra;
        }
      }
      ASSERT_EQ(and_not(mask, engine.all_rays<256>()).popcount(), 0);
    }
  }
  std::cout << spheres << " spheres, " << hits << " ray hits all in their masks; " << extra
            << " extra bits where the origin is not within the margin of the surface\n";
  EXPECT_GT(hits, 100000u);
}

TEST(RegionMask, NodeSphereMaskHoldsTheTriangleSphereMask) {
  // Triangle spheres inside node spheres (radius rounded up as a BVH builder must), seen from
  // receivers in a world with coordinates up to 200 r: the float rounding of to_local is the point.
  const ShadowRays rays = rays_of(128, Falloff::Linear, 0.5f);
  const MaskEngine engine = engine_of(rays, MaskMode::Exact);
  Rng rng(7);
  int nonempty = 0;
  for (int trial = 0; trial < 200000; ++trial) {
    const Frame frame = random_frame(rng, rays, 100.0f);
    const double node_radius = 0.5 * std::pow(10.0, -2.0 + 2.5 * rng.uniform());
    const glm::dvec3 node_local = random_in_box(rng, glm::dvec3(-1.2), glm::dvec3(1.2)) * 0.5;
    const glm::vec3 node_centre(local_to_world(frame, node_local));
    // A triangle sphere inside: random radius and offset, then the node radius grown to hold it
    // in exact arithmetic on the stored floats.
    const double tri_radius = node_radius * rng.uniform();
    // Half of them touching the node sphere from inside: the tightest nesting.
    const double offset = (node_radius - tri_radius) * (trial % 2 == 0 ? 1.0 : rng.uniform());
    const glm::vec3 tri_centre(glm::dvec3(node_centre) + random_unit(rng) * offset);
    const float tri_radius_f = static_cast<float>(tri_radius);
    const double need = glm::length(glm::dvec3(tri_centre) - glm::dvec3(node_centre)) + tri_radius_f;
    const float node_radius_f = std::nextafter(static_cast<float>(need), 1e30f);
    const Mask<128> tri = engine.region_mask<128>(frame.to_local(tri_centre), tri_radius_f, kTriangleMargin);
    const Mask<128> node = engine.region_mask<128>(frame.to_local(node_centre), node_radius_f, kNodeMargin);
    nonempty += tri.any();
    ASSERT_EQ(and_not(tri, node).popcount(), 0) << "trial " << trial;
  }
  EXPECT_GT(nonempty, 10000);
}

TEST(TriangleMask, ExactModeEqualsRayCastingInDouble) {
  std::size_t rays_tested = 0, disagree = 0;
  for (const int n : {128, 1024}) {
    for (const Falloff falloff : {Falloff::Constant, Falloff::Linear}) {
      const ShadowRays rays = rays_of(n, falloff, 0.75f);
      const MaskEngine engine = engine_of(rays, MaskMode::Exact);
      Rng rng(static_cast<std::uint64_t>(n) * 3 + static_cast<std::uint64_t>(falloff));
      with_mask_bits(n, [&](auto bits) {
        constexpr int Bits = decltype(bits)::value;
        for (int trial = 0; trial < 1500; ++trial) {
          const Frame frame = random_frame(rng, rays, 20.0f);
          // Vertices in units of r around the receiver: some big, some small, some crossing the horizon.
          const double size = std::pow(10.0, -1.5 + 1.7 * rng.uniform());
          const glm::dvec3 middle = random_in_box(rng, {-0.8, -0.8, -0.2}, {0.8, 0.8, 0.9});
          const glm::dvec3 a = middle + size * random_unit(rng), b = middle + size * random_unit(rng),
                           c = middle + size * random_unit(rng);
          const bool two_sided = rng.below(2) == 1;
          const TriangleSet set = one_triangle(frame, rays.radius, a, b, c, two_sided);
          const Mask<Bits> mask = engine.triangle_mask<Bits>(set, 0, frame);
          // The reference from the stored floats, moved into the frame in double.
          const double inv_r = 1.0 / rays.radius;
          const glm::dvec3 la = world_to_local(frame, glm::dvec3(set.v0[0])) * inv_r;
          const glm::dvec3 lb = world_to_local(frame, glm::dvec3(set.v1[0])) * inv_r;
          const glm::dvec3 lc = world_to_local(frame, glm::dvec3(set.v2[0])) * inv_r;
          for (int i = 0; i < n; ++i) {
            const bool hit = segment_hits(la, lb, lc, two_sided, glm::dvec3(rays.pattern.directions[i]),
                                          rays.pattern.lengths[i]);
            ++rays_tested;
            disagree += hit != mask.test(i);
          }
        }
      });
    }
  }
  const double agreement = 1.0 - static_cast<double>(disagree) / static_cast<double>(rays_tested);
  std::cout << "exact triangle masks vs double ray casting: " << disagree << " of " << rays_tested
            << " rays differ (agreement " << 100.0 * agreement << "%)\n";
  EXPECT_GE(agreement, 0.99999);
}

// A random triangle near the receiver of `frame`, of a size from 0.003 to 1.6 r.
TriangleSet random_nearby_triangle(Rng& rng, const Frame& frame, float radius);

// Every instruction set the CPU runs gives the scalar twin's bits: triangle, region and plane
// masks, at every N, in both mask modes (DESIGN.md section 8.6).
TEST(TriangleMask, EveryInstructionSetEqualsTheScalarTwin) {
  std::cout << "instruction sets tested:";
  for (const Isa isa : supported_isas()) std::cout << ' ' << isa_name(isa);
  std::cout << " (default " << isa_name(default_isa()) << ")\n";
  for (const int n : {32, 64, 96, 128, 256, 512, 1024}) {
    const ShadowRays rays = rays_of(n, Falloff::Linear, 1.5f);
    for (const MaskMode mode : {MaskMode::Exact, MaskMode::Lut}) {
      auto built = MaskEngine::build(rays, mode, 24, Isa::Scalar);
      ASSERT_TRUE(built);
      const MaskEngine scalar = std::move(*built);
      for (const Isa isa : supported_isas()) {
        auto other = MaskEngine::build(rays, mode, 24, isa);
        ASSERT_TRUE(other);
        const MaskEngine& engine = *other;
        ASSERT_EQ(engine.isa(), isa);
        Rng rng(static_cast<std::uint64_t>(n));
        with_mask_bits(n, [&](auto bits) {
          constexpr int Bits = decltype(bits)::value;
          int nonempty = 0;
          for (int trial = 0; trial < 1500; ++trial) {
            const Frame frame = random_frame(rng, rays, 10.0f);
            const TriangleSet set = random_nearby_triangle(rng, frame, rays.radius);
            const Mask<Bits> vector = engine.triangle_mask<Bits>(set, 0, frame);
            nonempty += vector.any();
            ASSERT_EQ(vector, scalar.triangle_mask<Bits>(set, 0, frame)) << isa_name(isa) << ' ' << n << ' ' << trial;
            const glm::vec3 centre = frame.to_local(set.centre[0]);
            ASSERT_EQ((engine.region_mask<Bits>(centre, set.radius[0], kNodeMargin)),
                      (scalar.region_mask<Bits>(centre, set.radius[0], kNodeMargin)));
            const Plane plane{glm::vec3(random_unit(rng)), static_cast<float>(rng.uniform())};
            ASSERT_EQ(engine.plane_mask<Bits>(plane), scalar.plane_mask<Bits>(plane));
            // Bits at or beyond N are never set.
            ASSERT_EQ(and_not(vector, engine.all_rays<Bits>()).popcount(), 0);
          }
          EXPECT_GT(nonempty, 100) << n;
        });
      }
    }
  }
}

// The BVH traversal sets up a leaf's triangles in lanes (bvh/leaf_setup-inl.h) and finishes each
// with lut's kernel: every triangle's mask must be the one-triangle kernel's, bit for bit, at
// every N, in both mask modes, for every cluster subset, on every instruction set; the scene
// mixes sizes, orientations, one- and two-sided triangles, slivers and triangles through the
// receiver, so that every cull of the set-up decides some lane.
TEST(TriangleMask, LeafSetupInLanesEqualsTheOneTriangleKernel) {
  Rng scene_rng(7);
  Scene scene;
  const float r = 1.5f;
  for (int t = 0; t < 160; ++t) {
    const glm::dvec3 middle = random_in_box(scene_rng, glm::dvec3(-1.2 * r), glm::dvec3(1.2 * r));
    const double size = r * std::pow(10.0, -2.0 + 2.3 * scene_rng.uniform());
    glm::dvec3 a = middle + size * random_unit(scene_rng), b = middle + size * random_unit(scene_rng);
    glm::dvec3 c = middle + size * random_unit(scene_rng);
    if (t % 10 == 3) c = a + (b - a) * 0.5 + 1e-7 * random_unit(scene_rng);  // a sliver
    scene.add_triangle(glm::vec3(a), glm::vec3(b), glm::vec3(c), scene_rng.uniform() < 0.5, 0);
  }
  const TriangleSet set = TriangleSet::build(scene);
  auto built = bvh::Bvh::build(set, {4, 8});
  ASSERT_TRUE(built) << built.error().message;
  const bvh::Bvh& tree = *built;
  // Every row width (bvh::leaf_width): leaves of up to 2 triangles keep rows of 2, up to 4 rows
  // of 4, larger 8.
  const auto has_width = [&](int width) {
    return std::any_of(tree.nodes.begin(), tree.nodes.end(), [&](const bvh::Node& node) {
      return std::any_of(node.leaf_size, node.leaf_size + node.child_count,
                         [&](std::uint8_t size) { return size != 0 && bvh::leaf_width(size) == width; });
    });
  };
  ASSERT_TRUE(has_width(2) && has_width(4) && has_width(8));
  for (const int n : {32, 64, 128, 256, 512, 1024}) {
    const ShadowRays rays = rays_of(n, Falloff::Linear, r);
    for (const MaskMode mode : {MaskMode::Exact, MaskMode::Lut}) {
      for (const Isa isa : supported_isas()) {
        auto made = MaskEngine::build(rays, mode, 24, isa);
        ASSERT_TRUE(made);
        const MaskEngine& engine = *made;
        Rng rng(static_cast<std::uint64_t>(n) * 31 + static_cast<std::uint64_t>(isa));
        with_mask_bits(n, [&](auto bits) {
          constexpr int Bits = decltype(bits)::value;
          int nonempty = 0;
          for (int trial = 0; trial < 40; ++trial) {
            // Receivers inside the cloud (a few on a triangle's own vertex).
            Frame frame = random_frame(rng, rays, r);
            if (trial % 8 == 0) frame.origin = set.v1[rng.next() % set.size()];
            const std::uint64_t allowed = trial % 2 ? kAllClusters<Bits> : (rng.next() & kAllClusters<Bits>);
            for (const bvh::Node& node : tree.nodes) {
              for (int k = 0; k < node.child_count; ++k) {
                if (node.leaf_size[k] == 0) continue;
                Mask<Bits> lanes[bvh::LeafBlock::kLanes];
                bvh::leaf_masks<Bits>(tree, engine, frame, node.child[k], node.leaf_size[k], allowed, lanes);
                const std::uint32_t first = tree.leaf_at(node.child[k]).first;
                for (int l = 0; l < node.leaf_size[k]; ++l) {
                  const Mask<Bits> one = engine.triangle_mask<Bits>(set, tree.scene_triangle[first + l], frame, allowed);
                  nonempty += one.any();
                  ASSERT_EQ(lanes[l], one) << isa_name(isa) << " N " << n << " trial " << trial << " triangle "
                                           << first + l;
                }
              }
            }
          }
          EXPECT_GT(nonempty, 50) << isa_name(isa) << ' ' << n;
        });
      }
    }
  }
}

// The cluster culling of lut/kernels-inl.h skips work only: with it on, every mask equals the
// mask computed on every cluster; a mask asked for some clusters is the full mask on those; and
// a cull made too tight (cones shrunk by a negative slack) is caught by this very comparison.
TEST(TriangleMask, ClusterCullingChangesNoBitAndATighterCullIsCaught) {
  for (const int n : {64, 128, 1024}) {
    for (const Falloff falloff : {Falloff::Constant, Falloff::Linear}) {
      const ShadowRays rays = rays_of(n, falloff, 1.5f);
      for (const MaskMode mode : {MaskMode::Exact, MaskMode::Lut}) {
        MaskEngine culled = engine_of(rays, mode, 32);
        MaskEngine every = engine_of(rays, mode, 32);
        MaskEngine tight = engine_of(rays, mode, 32);
        every.set_cluster_culling_for_test(false, kClusterSlack);
        // Too tight by 0.05 in cosine; by 0.15 at N <= 128, whose few wide clusters rarely meet a
        // triangle's cone at their border (the near samples, which caught the smaller error, now
        // serve only where they are cheaper than the vectors).
        tight.set_cluster_culling_for_test(true, n <= 128 ? -0.15f : -0.05f);
        Rng rng(static_cast<std::uint64_t>(n) * 7 + static_cast<std::uint64_t>(mode));
        with_mask_bits(n, [&](auto bits) {
          constexpr int Bits = decltype(bits)::value;
          int nonempty = 0, tight_differs = 0;
          for (int trial = 0; trial < 4000; ++trial) {
            const Frame frame = random_frame(rng, rays, 10.0f);
            const TriangleSet set = random_nearby_triangle(rng, frame, rays.radius);
            const Mask<Bits> reference = every.triangle_mask<Bits>(set, 0, frame);
            nonempty += reference.any();
            ASSERT_EQ(culled.triangle_mask<Bits>(set, 0, frame), reference) << n << ' ' << trial;
            tight_differs += tight.triangle_mask<Bits>(set, 0, frame) != reference;
            const std::uint64_t some = rng.next() & kAllClusters<Bits>;
            ASSERT_EQ(culled.triangle_mask<Bits>(set, 0, frame, some), reference & cluster_bits<Bits>(some));
            const glm::vec3 centre = frame.to_local(set.centre[0]);
            const float grown = set.radius[0] * static_cast<float>(1.0 + 3.0 * rng.uniform());
            const Mask<Bits> region = every.region_mask<Bits>(centre, grown, kNodeMargin);
            ASSERT_EQ(culled.region_mask<Bits>(centre, grown, kNodeMargin), region);
            ASSERT_EQ(culled.region_mask<Bits>(centre, grown, kNodeMargin, some), region & cluster_bits<Bits>(some));
            tight_differs += tight.region_mask<Bits>(centre, grown, kNodeMargin) != region;
          }
          EXPECT_GT(nonempty, 250) << n;
          EXPECT_GT(tight_differs, 10) << "a too-tight cluster cull went unnoticed at N = " << n;
        });
      }
    }
  }
}

TriangleSet random_nearby_triangle(Rng& rng, const Frame& frame, float radius) {
  const glm::dvec3 middle = random_in_box(rng, {-0.8, -0.8, -0.2}, {0.8, 0.8, 0.9});
  const double size = std::pow(10.0, -2.5 + 2.7 * rng.uniform());
  const glm::dvec3 a = middle + size * random_unit(rng), b = middle + size * random_unit(rng),
                   c = middle + size * random_unit(rng);
  return one_triangle(frame, radius, a, b, c, true);
}

TEST(TriangleMask, LutMasksStayInsideTheTrianglesRegionMask) {
  const ShadowRays rays = rays_of(128, Falloff::Constant, 1.0f);
  const MaskEngine engine = engine_of(rays, MaskMode::Lut);
  Rng rng(3);
  for (int trial = 0; trial < 20000; ++trial) {
    const Frame frame = random_frame(rng, rays, 10.0f);
    // Slivers: two close vertices and one far, the case whose table edge masks leak far away.
    const glm::dvec3 a = random_in_box(rng, {-0.8, -0.8, 0.0}, {0.8, 0.8, 0.9});
    const glm::dvec3 b = a + 0.01 * random_unit(rng);
    const glm::dvec3 c = a + 0.5 * random_unit(rng);
    const TriangleSet set = one_triangle(frame, rays.radius, a, b, c, true);
    const Mask<128> mask = engine.triangle_mask<128>(set, 0, frame);
    const Mask<128> region = engine.region_mask<128>(frame.to_local(set.centre[0]), set.radius[0], kTriangleMargin);
    ASSERT_EQ(and_not(mask, region).popcount(), 0);
  }
}

TEST(TriangleMask, OneSidedTriangleSeenFromBehindBlocksNothing) {
  const ShadowRays rays = rays_of(128, Falloff::Constant, 1.0f);
  for (const MaskMode mode : {MaskMode::Exact, MaskMode::Lut}) {
    const MaskEngine engine = engine_of(rays, mode);
    Frame frame;  // the identity frame at the world origin
    // A roof at height 0.5 r over the receiver. Facing down (towards the receiver): its CCW
    // normal must point to -z, i.e. clockwise seen from above.
    const glm::dvec3 a{-3.0, -3.0, 0.5}, b{3.0, -3.0, 0.5}, c{0.0, 3.0, 0.5};
    const TriangleSet facing = one_triangle(frame, 1.0f, a, c, b, false);
    const TriangleSet away = one_triangle(frame, 1.0f, a, b, c, false);
    const TriangleSet both = one_triangle(frame, 1.0f, a, b, c, true);
    const Mask<128> m_facing = engine.triangle_mask<128>(facing, 0, frame);
    const Mask<128> m_away = engine.triangle_mask<128>(away, 0, frame);
    const Mask<128> m_both = engine.triangle_mask<128>(both, 0, frame);
    EXPECT_TRUE(m_away.none()) << mask_mode_name(mode);
    EXPECT_TRUE(m_facing.any());
    EXPECT_EQ(m_facing, m_both);
    // With constant falloff every point is on the unit hemisphere: the roof blocks exactly the
    // rays with z >= 0.5 (within the table's resolution in Lut mode).
    int expected = 0;
    for (const glm::vec3& p : rays.pattern.points) expected += p.z >= 0.5f;
    if (mode == MaskMode::Exact) {
      EXPECT_EQ(m_facing.popcount(), expected);
    } else {
      EXPECT_NEAR(m_facing.popcount(), expected, 4);
    }
    // Below the horizon, beyond r, out of reach, or through the origin (d = 0): nothing.
    const auto mask_of = [&](glm::dvec3 p, glm::dvec3 q, glm::dvec3 s) {
      return engine.triangle_mask<128>(one_triangle(frame, 1.0f, p, q, s, true), 0, frame);
    };
    EXPECT_TRUE(mask_of({-3, -3, -0.1}, {3, -3, -0.1}, {0, 3, -0.1}).none());
    EXPECT_TRUE(mask_of({-3, -3, 1.01}, {3, -3, 1.01}, {0, 3, 1.01}).none());
    EXPECT_TRUE(mask_of({2, 0, 0.1}, {3, 0, 0.1}, {2, 1, 0.2}).none());
    EXPECT_TRUE(mask_of({0.1, -1, 0}, {0.1, 1, 0}, {0.1, 0, 1}).any());
    EXPECT_TRUE(mask_of({0, -1, 0}, {0, 1, 0}, {0, 0, 1}).none());
  }
}

TEST(TriangleMask, ModeNamesRoundTrip) {
  for (const MaskMode m : {MaskMode::Lut, MaskMode::Exact}) EXPECT_EQ(*parse_mask_mode(mask_mode_name(m)), m);
  auto bad = parse_mask_mode("fast");
  ASSERT_FALSE(bad);
  EXPECT_NE(bad.error().message.find("fast"), std::string::npos);
}

TEST(TriangleSet, SpheresHoldTheirTriangles) {
  Rng rng(11);
  Scene scene;
  for (int i = 0; i < 20000; ++i) {
    const glm::dvec3 o = random_in_box(rng, glm::dvec3(-1000.0), glm::dvec3(1000.0));
    const double s = std::pow(10.0, -3.0 + 4.0 * rng.uniform());
    scene.add_triangle(glm::vec3(o + s * random_unit(rng)), glm::vec3(o + s * random_unit(rng)),
                       glm::vec3(o + s * random_unit(rng)), false, 0);
  }
  const TriangleSet set = TriangleSet::build(scene);
  ASSERT_EQ(set.size(), scene.triangle_count());
  for (std::size_t t = 0; t < set.size(); ++t) {
    const glm::dvec3 c(set.centre[t]);
    double longest = 0.0;
    for (const glm::vec3& v : {set.v0[t], set.v1[t], set.v2[t]}) {
      ASSERT_LE(glm::length(glm::dvec3(v) - c), double(set.radius[t])) << t;
    }
    for (const auto& [p, q] : {std::pair{set.v0[t], set.v1[t]}, {set.v1[t], set.v2[t]}, {set.v2[t], set.v0[t]}}) {
      longest = std::max(longest, glm::length(glm::dvec3(p) - glm::dvec3(q)));
    }
    // The smallest sphere: never bigger than the circumsphere, never smaller than half the longest edge.
    ASSERT_GE(double(set.radius[t]), 0.5 * longest * (1.0 - 1e-6));
    ASSERT_LE(double(set.radius[t]), longest / std::sqrt(3.0) * (1.0 + 1e-4) + 1e-6 * glm::length(c));
  }
}

}  // namespace
}  // namespace exao::lut
