// The public API's renderer hooks (issue 22, items 2 and 5), through the public header only:
//  - the default origin offset follows the point, not the scene's box;
//  - instances: a mesh placed many times gives the bits of the same triangles given as copies;
//  - refit after a deformation equals a fresh build, bit for bit, in every backend;
//  - a receiver can exclude an object, in every backend the same way (0 rays differ from the
//    embree backend, which excludes by its occlusion filter);
//  - caller-supplied directions: bit i is direction i, the same in every backend, in the
//    caller's (incoherent) order too: a cluster of 16 directions wider than a hemisphere's half
//    gets conservative cone bounds (lut/sample_arrays.h).

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <random>
#include <span>
#include <string>
#include <vector>

#include "exao/exao.hpp"

#define EXAO_EXPECT_OK(status) EXPECT_TRUE(status) << ((status) ? std::string() : (status).error().message)

namespace exao::api {
namespace {

// --- Scenes -----------------------------------------------------------------------------------

// A closed, indexed box [-1, 1]^3 with outward (counter-clockwise) faces: 8 vertices, 12 triangles.
struct Box {
  std::array<float, 24> vertices{-1, -1, -1, 1, -1, -1, 1, 1, -1, -1, 1, -1, -1, -1, 1, 1, -1, 1, 1, 1, 1, -1, 1, 1};
  std::array<std::uint32_t, 36> indices{0, 2, 1, 0, 3, 2, 4, 5, 6, 4, 6, 7, 0, 1, 5, 0, 5, 4,
                                        3, 6, 2, 3, 7, 6, 0, 4, 7, 0, 7, 3, 1, 2, 6, 1, 6, 5};

  [[nodiscard]] Mesh mesh(const float* transform = nullptr) const {
    Mesh m;
    m.vertices = vertices.data();
    m.vertex_count = 8;
    m.indices = indices.data();
    m.triangle_count = 12;
    m.transform = transform;
    return m;
  }
};

// A ground grid of n x n quads on z = 0, [-size, size]^2, as a soup; z displaced by `wave`.
std::vector<float> ground(int n, float size, float wave) {
  std::vector<float> out;
  const auto at = [&](int i, int j) {
    const float x = -size + 2.0f * size * static_cast<float>(i) / static_cast<float>(n);
    const float y = -size + 2.0f * size * static_cast<float>(j) / static_cast<float>(n);
    return std::array<float, 3>{x, y, wave * std::sin(1.3f * x) * std::cos(0.7f * y)};
  };
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      for (const auto& v : {at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j), at(i + 1, j + 1), at(i, j + 1)}) {
        out.insert(out.end(), v.begin(), v.end());
      }
    }
  }
  return out;
}

Mesh soup(const std::vector<float>& v) {
  Mesh m;
  m.vertices = v.data();
  m.vertex_count = v.size() / 3;
  m.triangle_count = v.size() / 9;
  return m;
}

// Row-major 3x4: uniform scale s, then a translation.
std::array<float, 12> placement(float s, float x, float y, float z) { return {s, 0, 0, x, 0, s, 0, y, 0, 0, s, z}; }

// Receivers spread over the scene's box [-4, 4]^2 x [0, 2], random normals, random keys.
std::vector<Receiver> receivers(std::size_t count, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> xy(-4.0f, 4.0f), z(0.05f, 2.0f), n(-1.0f, 1.0f);
  std::vector<Receiver> out(count);
  for (Receiver& r : out) r = {{xy(rng), xy(rng), z(rng)}, {n(rng), n(rng), n(rng) + 0.2f}, rng()};
  return out;
}

std::vector<std::uint64_t> batch_masks(const Engine& engine, std::span<const Receiver> rs) {
  std::vector<std::uint64_t> words(rs.size() * engine.mask_words());
  const Status ok = engine.masks(rs, words);
  EXAO_EXPECT_OK(ok);
  return words;
}

// Rays whose bits differ between two batches of masks.
std::size_t differing_rays(const std::vector<std::uint64_t>& a, const std::vector<std::uint64_t>& b) {
  EXPECT_EQ(a.size(), b.size());
  std::size_t n = 0;
  for (std::size_t i = 0; i < a.size() && i < b.size(); ++i) n += static_cast<std::size_t>(std::popcount(a[i] ^ b[i]));
  return n;
}

std::size_t blocked_rays(const std::vector<std::uint64_t>& a) {
  std::size_t n = 0;
  for (const std::uint64_t w : a) n += static_cast<std::size_t>(std::popcount(w));
  return n;
}

Options options_for(Backend backend) {
  Options o;
  o.samples = 64;
  o.radius = 3.0f;
  o.backend = backend;
  o.threads = 2;
  return o;
}

QuerySettings radius_setting(float r) {
  QuerySettings s;
  s.radius = r;
  return s;
}
QuerySettings samples_setting(int n) {
  QuerySettings s;
  s.samples = n;
  return s;
}

constexpr Backend kBackends[] = {Backend::Auto, Backend::Bvh, Backend::Brute, Backend::Embree};


// --- Item 2: the API's default offset -----------------------------------------------------------

TEST(RendererHooks, DefaultOffsetFollowsThePointNotTheSceneBox) {
  const Box box;
  const std::vector<float> far_triangle{5000, 5000, 0, 5001, 5000, 0, 5000, 5001, 0};
  const Mesh near_only[] = {box.mesh()};
  const Mesh with_far[] = {box.mesh(), soup(far_triangle)};
  Options o;
  o.samples = 32;
  Result<Engine> a = Engine::build(near_only, o);
  Result<Engine> b = Engine::build(with_far, o);
  ASSERT_TRUE(a && b);
  // The box's diagonal was 3.46, then ~7000 with the far triangle: the scene's offset would move
  // 2000-fold. The point's own offset does not move at all.
  EXPECT_FLOAT_EQ(a->info().origin_offset_per_magnitude, 1e-4f);
  EXPECT_EQ(a->info().origin_offset, b->info().origin_offset);
  for (const Vec3 p : {Vec3{0.5f, -0.25f, 1.0f}, Vec3{3.0f, 2.0f, -7.0f}, Vec3{0.0f, 0.0f, 1e-9f}}) {
    const Receiver r{p, {0.0f, 0.0f, 1.0f}, 7};
    std::vector<ShadowRay> rays(32);
    Vec3 oa, ob;
    EXAO_EXPECT_OK(a->rays(r, oa, rays));
    EXAO_EXPECT_OK(b->rays(r, ob, rays));
    EXPECT_EQ(oa.z, ob.z);
    const float magnitude = std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z)});
    EXPECT_EQ(oa.z, p.z + std::max(1e-6f, 1e-4f * magnitude)) << p.x;
  }
  // An offset given is used as it is, at every point.
  o.origin_offset = 0.01f;
  Result<Engine> c = Engine::build(with_far, o);
  ASSERT_TRUE(c);
  EXPECT_EQ(c->info().origin_offset, 0.01f);
  EXPECT_EQ(c->info().origin_offset_per_magnitude, 0.0f);
}

// --- Item 5: instances --------------------------------------------------------------------------

TEST(RendererHooks, InstancesGiveTheBitsOfTheSameTrianglesGivenAsCopies) {
  const Box box;
  const std::vector<float> floor = ground(8, 5.0f, 0.0f);
  std::vector<std::array<float, 12>> transforms;
  for (int i = 0; i < 9; ++i) {
    const auto f = static_cast<float>(i);
    transforms.push_back(placement(0.3f + 0.05f * f, -3.0f + 0.75f * f, 0.6f * static_cast<float>(i % 3), 0.5f));
  }
  const Mesh meshes[] = {soup(floor), box.mesh()};
  std::vector<Instance> instances{{0, nullptr}};
  std::vector<Mesh> copies{soup(floor)};
  for (const auto& m : transforms) {
    instances.push_back({1, m.data()});
    copies.push_back(box.mesh(m.data()));
  }
  const std::vector<Receiver> rs = receivers(400, 3);
  std::vector<std::uint64_t> reference;
  for (const Backend backend : kBackends) {
    Result<Engine> placed = Engine::build(meshes, instances, options_for(backend));
    Result<Engine> copied = Engine::build(copies, options_for(backend));
    ASSERT_TRUE(placed) << placed.error().message;
    ASSERT_TRUE(copied);
    EXPECT_EQ(placed->info().triangles, 128u + 9u * 12u);
    const std::vector<std::uint64_t> m = batch_masks(*placed, rs);
    EXPECT_EQ(differing_rays(m, batch_masks(*copied, rs)), 0u);
    if (backend == Backend::Auto) reference = m;
    if (backend != Backend::Bvh && backend != Backend::Brute) {
      EXPECT_EQ(differing_rays(m, reference), 0u);
    }
  }
  EXPECT_GT(blocked_rays(reference), rs.size() * 4);  // the instances are there
  // Errors name the instance.
  const Instance bad[] = {{2, nullptr}};
  Result<Engine> wrong = Engine::build(meshes, bad);
  ASSERT_FALSE(wrong);
  EXPECT_NE(wrong.error().message.find("instances[0].mesh"), std::string::npos) << wrong.error().message;
}

// --- Item 5: refit -----------------------------------------------------------------------------

TEST(RendererHooks, RefitEqualsAFreshBuildInEveryBackend) {
  const Box box;
  std::vector<float> floor = ground(10, 5.0f, 0.0f);
  std::array<float, 12> moving = placement(0.8f, 0.0f, 0.0f, 1.0f);
  const std::vector<Receiver> rs = receivers(400, 5);
  for (const Backend backend : kBackends) {
    SCOPED_TRACE(static_cast<int>(backend));
    const Mesh meshes[] = {soup(floor), box.mesh()};
    std::vector<Instance> instances{{0, nullptr}, {1, moving.data()}};
    Result<Engine> engine = Engine::build(meshes, instances, options_for(backend));
    ASSERT_TRUE(engine);
    Result<Engine> wider = engine->with_settings(radius_setting(5.0f));
    ASSERT_TRUE(wider);
    const std::vector<std::uint64_t> before = batch_masks(*engine, rs);

    // Deform: the ground waves (the same triangles, new positions), the box moves and grows.
    std::vector<float> deformed = ground(10, 5.0f, 0.6f);
    std::array<float, 12> moved = placement(1.1f, 1.5f, -0.5f, 1.2f);
    const Mesh after[] = {soup(deformed), box.mesh()};
    const std::vector<Instance> after_instances{{0, nullptr}, {1, moved.data()}};
    EXAO_EXPECT_OK(engine->refit(after, after_instances));
    Result<Engine> fresh = Engine::build(after, after_instances, options_for(backend));
    ASSERT_TRUE(fresh);
    const std::vector<std::uint64_t> refitted = batch_masks(*engine, rs);
    EXPECT_EQ(differing_rays(refitted, batch_masks(*fresh, rs)), 0u);
    EXPECT_GT(differing_rays(refitted, before), rs.size());  // the scene did move
    // Single queries, and the engine of other settings over the same scene, moved too.
    for (std::size_t i = 0; i < 20; ++i) {
      Result<RayMask> one = engine->mask(rs[i]);
      Result<RayMask> fresh_one = fresh->mask(rs[i]);
      ASSERT_TRUE(one && fresh_one);
      EXPECT_EQ(one->words, fresh_one->words);
    }
    Result<Engine> fresh_wider = fresh->with_settings(radius_setting(5.0f));
    ASSERT_TRUE(fresh_wider);
    EXPECT_EQ(differing_rays(batch_masks(*wider, rs), batch_masks(*fresh_wider, rs)), 0u);
    EXPECT_EQ(engine->info().bounds_hi.z, fresh->info().bounds_hi.z);

    // What differs from build is refused, naming it, and changes nothing.
    const std::vector<float> smaller = ground(9, 5.0f, 0.0f);
    const Mesh other[] = {soup(smaller), box.mesh()};
    const Status refused = engine->refit(other, after_instances);
    ASSERT_FALSE(refused);
    EXPECT_NE(refused.error().message.find("instances[0] (meshes[0]).triangle_count"), std::string::npos)
        << refused.error().message;
    EXPECT_FALSE(engine->refit(after));  // built with instances
    EXPECT_EQ(differing_rays(batch_masks(*engine, rs), refitted), 0u);
  }
}

// --- Item 5: an object a receiver excludes -----------------------------------------------------

TEST(RendererHooks, ExcludedObjectIsSkippedTheSameWayInEveryBackend) {
  const Box box;
  const std::vector<float> floor = ground(12, 5.0f, 0.3f);
  std::vector<std::array<float, 12>> transforms;
  for (int i = 0; i < 6; ++i) {
    transforms.push_back(placement(0.5f, -2.5f + static_cast<float>(i), 0.4f * static_cast<float>(i % 2), 0.7f));
  }
  const Mesh meshes[] = {soup(floor), box.mesh()};
  std::vector<Instance> instances{{0, nullptr}};
  for (const auto& m : transforms) instances.push_back({1, m.data()});

  // Receivers on each box's faces (their outward normal) and inside them, excluding their own
  // box: the shading point of an object that must not shadow itself. Then ground points that
  // exclude the ground, and random points that exclude a random object or none.
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(-0.9f, 0.9f);
  std::vector<Receiver> rs;
  for (std::uint32_t k = 1; k < instances.size(); ++k) {
    const auto& m = transforms[k - 1];
    for (int i = 0; i < 40; ++i) {
      const int axis = i % 3;
      const float side = i % 2 ? 1.0f : -1.0f;
      float local[3] = {u(rng), u(rng), u(rng)};
      local[axis] = side;
      float normal[3] = {0, 0, 0};
      normal[axis] = side;
      if (i % 5 == 0) local[axis] = 0.5f * side;  // inside the box, looking out
      const Vec3 p{m[0] * local[0] + m[3], m[5] * local[1] + m[7], m[10] * local[2] + m[11]};
      rs.push_back({p, {normal[0], normal[1], normal[2]}, rng(), k});
    }
  }
  for (int i = 0; i < 80; ++i) rs.push_back({{u(rng) * 4.0f, u(rng) * 4.0f, 0.3f}, {0, 0, 1}, rng(), 0});
  for (Receiver r : receivers(200, 13)) {
    r.excluded_object = rng() % 3 == 0 ? kNoObject : static_cast<std::uint32_t>(rng() % instances.size());
    rs.push_back(r);
  }
  std::vector<Receiver> unexcluded = rs;
  for (Receiver& r : unexcluded) r.excluded_object = kNoObject;

  Result<Engine> embree = Engine::build(meshes, instances, options_for(Backend::Embree));
  ASSERT_TRUE(embree);
  const std::vector<std::uint64_t> reference = batch_masks(*embree, rs);
  // Exclusion matters: the points inside a box are fully blocked unless it is excluded.
  EXPECT_GT(differing_rays(reference, batch_masks(*embree, unexcluded)), rs.size() * 2);
  for (const Backend backend : {Backend::Auto, Backend::Bvh, Backend::Brute}) {
    SCOPED_TRACE(static_cast<int>(backend));
    Result<Engine> engine = Engine::build(meshes, instances, options_for(backend));
    ASSERT_TRUE(engine);
    EXPECT_EQ(differing_rays(batch_masks(*engine, rs), reference), 0u);
    for (std::size_t i = 0; i < rs.size(); i += 7) {
      Result<RayMask> one = engine->mask(rs[i]);
      ASSERT_TRUE(one);
      EXPECT_EQ(std::vector<std::uint64_t>(one->words.begin(), one->words.begin() + 1),
                std::vector<std::uint64_t>(reference.begin() + static_cast<std::ptrdiff_t>(i),
                                           reference.begin() + static_cast<std::ptrdiff_t>(i + 1)));
    }
  }
}

// --- Item 5: the caller's own directions --------------------------------------------------------

TEST(RendererHooks, CallerDirectionsAreTheRaysOfEveryBackend) {
  const Box box;
  const std::vector<float> floor = ground(10, 5.0f, 0.4f);
  std::vector<std::array<float, 12>> transforms;
  for (int i = 0; i < 5; ++i) {
    const auto f = static_cast<float>(i);
    transforms.push_back(placement(0.6f, -2.0f + f, 0.3f * f - 0.6f, 0.8f));
  }
  const Mesh meshes[] = {soup(floor), box.mesh()};
  std::vector<Instance> instances{{0, nullptr}};
  for (const auto& m : transforms) instances.push_back({1, m.data()});

  // 96 directions of a renderer's own sampler (uniform on the hemisphere, in its own order),
  // not unit: exao normalises them. Lengths of a falloff of its own.
  std::mt19937 rng(17);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::vector<Vec3> directions(96);
  std::vector<float> lengths(96);
  for (std::size_t i = 0; i < directions.size(); ++i) {
    const float z = 0.02f + 0.98f * u(rng), phi = 6.2831853f * u(rng), s = std::sqrt(1.0f - z * z);
    directions[i] = {2.0f * s * std::cos(phi), 2.0f * s * std::sin(phi), 2.0f * z};
    lengths[i] = 0.1f + 0.9f * u(rng);
  }
  QuerySettings settings;
  settings.directions = directions;
  settings.lengths = lengths;
  const std::vector<Receiver> rs = receivers(300, 19);

  Result<Engine> embree_base = Engine::build(meshes, instances, options_for(Backend::Embree));
  ASSERT_TRUE(embree_base);
  Result<Engine> embree = embree_base->with_settings(settings);
  ASSERT_TRUE(embree) << embree.error().message;
  EXPECT_EQ(embree->samples(), 96);
  const std::vector<std::uint64_t> reference = batch_masks(*embree, rs);
  EXPECT_GT(blocked_rays(reference), rs.size() * 4);
  // Ray i is direction i (turned by the receiver's frame) at length l_i r.
  std::vector<ShadowRay> rays(96);
  Vec3 origin;
  EXAO_EXPECT_OK(embree->rays(rs[0], origin, rays));
  for (std::size_t i = 0; i < rays.size(); ++i) {
    EXPECT_FLOAT_EQ(rays[i].length, lengths[i] * 3.0f);
    const Vec3 n = rs[0].normal;
    EXPECT_GT(rays[i].direction.x * n.x + rays[i].direction.y * n.y + rays[i].direction.z * n.z, 0.0f);
  }
  for (const Backend backend : {Backend::Auto, Backend::Bvh, Backend::Brute}) {
    SCOPED_TRACE(static_cast<int>(backend));
    Result<Engine> base = Engine::build(meshes, instances, options_for(backend));
    ASSERT_TRUE(base);
    Result<Engine> engine = base->with_settings(settings);
    ASSERT_TRUE(engine);
    EXPECT_EQ(differing_rays(batch_masks(*engine, rs), reference), 0u);
    // Back to the shared pattern with another N.
    Result<Engine> shared = engine->with_settings(samples_setting(64));
    ASSERT_TRUE(shared);
    EXPECT_EQ(shared->samples(), 64);
  }
  // Bad directions are refused naming the index.
  directions[5].z = -0.1f;
  Result<Engine> below = embree_base->with_settings(settings);
  ASSERT_FALSE(below);
  EXPECT_NE(below.error().message.find("settings.directions[5]"), std::string::npos) << below.error().message;
  settings.directions = std::span<const Vec3>(directions.data(), 40);
  settings.lengths = {};
  EXPECT_FALSE(embree_base->with_settings(settings));
}

}  // namespace
}  // namespace exao::api
