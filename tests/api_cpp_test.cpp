// The public C++ API (include/exao/exao.hpp): the same bits as `exao query` for the same points,
// keys, N, radius and mask mode, in every backend; single, mask and batch queries agree; many
// threads querying one engine at once get what one thread gets; meshes given as indexed,
// strided, transformed arrays give the scene's answer. Uses only the public header.

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <bit>
#include <limits>
#include <stdexcept>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <optional>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "exao/exao.hpp"
#include "tests/test_support.h"

namespace exao::api {
namespace {

// --- Helpers --------------------------------------------------------------------------------

Vec3 operator-(Vec3 a, Vec3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
Vec3 cross(Vec3 a, Vec3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
float dot(Vec3 a, Vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

Vec3 vertex(const SceneData& scene, std::size_t t, int j) {
  const float* p = scene.positions.data() + 9 * t + 3 * j;
  return {p[0], p[1], p[2]};
}

// Receivers on the scene's triangles (front side, so they see the open space of built-in
// scenes) with random 64-bit keys, plus a few anywhere in the bounding box with random normals.
std::vector<Receiver> surface_receivers(const SceneData& scene, std::size_t count, std::uint32_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  std::vector<Receiver> out;
  for (std::size_t i = 0; i < count; ++i) {
    const std::size_t t = rng() % scene.triangle_count();
    float u = unit(rng), v = unit(rng);
    if (u + v > 1.0f) u = 1.0f - u, v = 1.0f - v;
    const Vec3 a = vertex(scene, t, 0), b = vertex(scene, t, 1), c = vertex(scene, t, 2);
    const Vec3 p{a.x + u * (b.x - a.x) + v * (c.x - a.x), a.y + u * (b.y - a.y) + v * (c.y - a.y),
                 a.z + u * (b.z - a.z) + v * (c.z - a.z)};
    out.push_back({p, cross(b - a, c - a), rng() >> (i % 2 ? 0 : 40)});
  }
  return out;
}

using test::CommandResult;
using test::run_command;

// AO of `receivers` by `exao query <scene> <arguments>`, read back from its output file.
std::vector<float> exao_query(const std::string& scene, const std::vector<Receiver>& receivers, const std::string& arguments) {
  test::TempDir dir;
  {
    std::ofstream points(dir / "points.txt");
    char line[256];
    for (const Receiver& r : receivers) {
      std::snprintf(line, sizeof line, "%.9g %.9g %.9g %.9g %.9g %.9g %llu\n", r.position.x, r.position.y, r.position.z,
                    r.normal.x, r.normal.y, r.normal.z, static_cast<unsigned long long>(r.key));
      points << line;
    }
  }
  const CommandResult result = run_command(std::string(EXAO_BINARY) + " query " + scene + " --points " + (dir / "points.txt").string() +
                                   " -o " + (dir / "ao.txt").string() + " " + arguments);
  EXPECT_EQ(result.status, 0) << result.output;
  std::vector<float> ao;
  std::ifstream in(dir / "ao.txt");
  std::string value;
  while (in >> value) ao.push_back(std::strtof(value.c_str(), nullptr));
  return ao;
}

struct Case {
  std::string scene;
  Options options;
  std::string arguments;  // the same settings for exao query
};

std::string describe(const Case& c) { return c.scene + " " + c.arguments; }

// --- exao query equality --------------------------------------------------------------------

void expect_same_as_exao_query(const Case& given, std::size_t count) {
  // The API's default offset follows each point (exao.hpp, Options::origin_offset), the exao
  // program's the scene's diagonal (DESIGN.md section 1): both are given one offset here.
  Case c = given;
  if (!c.options.origin_offset) {
    c.options.origin_offset = 0.001f;
    c.arguments += " --offset 0.001";
  }
  SCOPED_TRACE(describe(c));
  Result<SceneData> scene = load_scene(c.scene);
  ASSERT_TRUE(scene) << scene.error().message;
  const std::vector<Receiver> receivers = surface_receivers(*scene, count, 7);
  const std::vector<float> expected = exao_query(c.scene, receivers, c.arguments);
  ASSERT_EQ(expected.size(), receivers.size());
  const auto partly = std::count_if(expected.begin(), expected.end(), [](float v) { return v > 0.0f && v < 1.0f; });
  EXPECT_GT(partly, static_cast<long>(receivers.size() / 10)) << "the points must see occlusion for the test to mean much";

  Result<Engine> engine = Engine::open(c.scene, c.options);
  ASSERT_TRUE(engine) << engine.error().message;
  std::vector<float> batch(receivers.size());
  ASSERT_TRUE(engine->ao(receivers, batch));
  std::vector<std::uint64_t> words(receivers.size() * engine->mask_words());
  ASSERT_TRUE(engine->masks(receivers, words));
  int differing = 0;
  for (std::size_t i = 0; i < receivers.size(); ++i) {
    Result<float> single = engine->ao(receivers[i]);
    ASSERT_TRUE(single) << single.error().message;
    Result<RayMask> mask = engine->mask(receivers[i]);
    ASSERT_TRUE(mask);
    // Exact float equality: the same blocked count over the same N.
    differing += *single != expected[i];
    EXPECT_EQ(*single, expected[i]) << "receiver " << i;
    EXPECT_EQ(batch[i], expected[i]) << "receiver " << i;
    EXPECT_EQ(mask->ao(), expected[i]) << "receiver " << i;
    for (std::size_t w = 0; w < engine->mask_words(); ++w) {
      ASSERT_EQ(words[i * engine->mask_words() + w], mask->words[w]) << "receiver " << i << " word " << w;
    }
    if (differing > 5) FAIL() << "too many differences";
  }
}

TEST(ApiCpp, SameAsExaoQueryBvhLut) {
  Options o;
  o.samples = 128;
  o.radius = 0.8f;
  o.backend = Backend::Bvh;
  o.mask_mode = MaskMode::Lut;
  expect_same_as_exao_query({"room", o, "-n 128 -r 0.8 --masks lut --method bvh"}, 1500);
}

TEST(ApiCpp, SameAsExaoQueryBvhExactDefaults) {
  Options o;  // default radius (5% of the diagonal) and mask mode (exact), N = 64; the offset: the helper's
  o.samples = 64;
  o.backend = Backend::Bvh;
  EXPECT_EQ(o.mask_mode, MaskMode::Exact);
  expect_same_as_exao_query({"room", o, "-n 64 --method bvh"}, 1500);
}

TEST(ApiCpp, SameAsExaoQueryAutoByDefault) {
  Options o;  // every default: the auto backend, as exao query's
  EXPECT_EQ(o.backend, Backend::Auto);
  expect_same_as_exao_query({"room", o, ""}, 1500);
}

TEST(ApiCpp, SameAsExaoQueryBruteN256) {
  Options o;
  o.samples = 256;
  o.radius = 0.6f;
  o.backend = Backend::Brute;
  o.falloff = Falloff::Linear;
  o.mask_mode = MaskMode::Lut;
  expect_same_as_exao_query({"room", o, "-n 256 -r 0.6 --falloff linear --masks lut --method brute"}, 400);
}

TEST(ApiCpp, SameAsExaoQueryEmbreeTwoSided) {
  Options o;
  o.samples = 64;
  o.radius = 0.5f;
  o.origin_offset = 0.001f;
  o.backend = Backend::Embree;
  o.sidedness = Sidedness::Two;
  expect_same_as_exao_query({"sphere-on-plane", o, "-n 64 -r 0.5 --offset 0.001 --sided two --method embree"}, 400);
}

// --- Consistency of the query kinds ---------------------------------------------------------

TEST(ApiCpp, RaysAreThePatternAboutTheNormal) {
  Options o;
  o.samples = 96;
  o.radius = 0.5f;
  o.falloff = Falloff::Quadratic;
  o.mask_mode = MaskMode::Exact;  // the look-up table may differ on rays grazing the ceiling
  Result<Engine> engine = Engine::open("plane-pair", o);
  ASSERT_TRUE(engine) << engine.error().message;
  EXPECT_EQ(engine->info().samples, 96);
  EXPECT_EQ(engine->mask_words(), 2u);
  const Receiver r{{0.1f, 0.0f, 0.2f}, {0.0f, 2.0f, 0.0f}, 42};
  std::vector<ShadowRay> rays(96), again(96);
  Vec3 origin;
  ASSERT_TRUE(engine->rays(r, origin, rays));
  // The default offset at this point: 1e-4 of its largest coordinate, 0.2 (at least 1e-6).
  EXPECT_EQ(engine->info().origin_offset_per_magnitude, 1e-4f);
  EXPECT_NEAR(origin.y, std::max(engine->info().origin_offset, 1e-4f * 0.2f), 1e-9f);
  Result<RayMask> mask = engine->mask(r, again);
  ASSERT_TRUE(mask);
  for (int i = 0; i < 96; ++i) {
    const Vec3 d = rays[static_cast<std::size_t>(i)].direction;
    EXPECT_NEAR(dot(d, d), 1.0f, 1e-5f);
    EXPECT_GT(d.y, 0.0f) << "every ray leaves the surface";
    EXPECT_GT(rays[static_cast<std::size_t>(i)].length, 0.0f);
    EXPECT_LE(rays[static_cast<std::size_t>(i)].length, 0.5f * (1.0f + 1e-6f));
    EXPECT_EQ(rays[static_cast<std::size_t>(i)].direction.x, again[static_cast<std::size_t>(i)].direction.x);
    // The ceiling is at 0.5 - offset above the origin: a ray is blocked iff it reaches it.
    const float reach = rays[static_cast<std::size_t>(i)].length * d.y;
    if (std::abs(reach - (0.5f - origin.y)) > 1e-4f) {
      EXPECT_EQ(mask->blocked(i), reach > 0.5f - origin.y) << i;
    }
  }
  for (std::size_t w = 0; w < mask->words.size(); ++w) {
    if (w >= 2) {
      EXPECT_EQ(mask->words[w], 0u) << "bits past N stay zero";
    }
  }
}

TEST(ApiCpp, PlanePairIsAnalytic) {
  // A point under a parallel plane at height h, constant falloff: AO = (h / r)^2 (DESIGN.md 6).
  Options o;
  o.samples = 1024;
  o.radius = 1.0f;
  o.origin_offset = 0.0f;
  o.mask_mode = MaskMode::Exact;
  Result<Engine> engine = Engine::open("plane-pair", o);
  ASSERT_TRUE(engine) << engine.error().message;
  double sum = 0.0;
  for (std::uint64_t k = 0; k < 64; ++k) sum += *engine->ao({0.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}, k);
  EXPECT_NEAR(sum / 64.0, 0.25, 0.01);
}

// --- Meshes from the caller's arrays --------------------------------------------------------

TEST(ApiCpp, MeshArraysGiveTheSceneAnswer) {
  Result<SceneData> scene = load_scene("room");
  ASSERT_TRUE(scene);
  EXPECT_FALSE(scene->cameras.empty());
  Options o;
  o.samples = 64;
  o.radius = 0.7f;
  Result<Engine> opened = Engine::open("room", o);
  Result<Engine> soup = Engine::build(scene->mesh(), o);
  ASSERT_TRUE(opened && soup);

  // The same triangles as an indexed mesh: interleaved vertices (x y z u v, stride 20 bytes),
  // triangle records of four indices (stride 16), in two meshes.
  struct Vertex {
    float x, y, z, u, v;
  };
  const std::size_t n = scene->triangle_count();
  std::vector<Vertex> vertices;
  std::vector<std::uint32_t> records;
  for (std::size_t t = 0; t < n; ++t) {
    for (int j = 2; j >= 0; --j) {  // stored in reverse, then indexed back in order
      const Vec3 p = vertex(*scene, t, j);
      vertices.push_back({p.x, p.y, p.z, 0.5f, 0.5f});
    }
    const auto base = static_cast<std::uint32_t>(3 * t);
    records.insert(records.end(), {base + 2, base + 1, base, 0xDEADu});
  }
  const std::size_t half = n / 2;
  Mesh a;
  a.vertices = &vertices[0].x;
  a.vertex_count = vertices.size();
  a.vertex_stride = sizeof(Vertex);
  a.indices = records.data();
  a.index_stride = 4 * sizeof(std::uint32_t);
  a.triangle_count = half;
  a.two_sided = scene->two_sided.data();
  Mesh b = a;
  b.indices = records.data() + 4 * half;
  b.triangle_count = n - half;
  b.two_sided = scene->two_sided.data() + half;
  const Mesh parts[] = {a, b};
  Result<Engine> indexed = Engine::build(parts, o);
  ASSERT_TRUE(indexed) << indexed.error().message;
  EXPECT_EQ(indexed->info().triangles, n);
  EXPECT_EQ(indexed->info().radius, 0.7f);

  const std::vector<Receiver> receivers = surface_receivers(*scene, 500, 3);
  for (const Receiver& r : receivers) {
    const float expected = *opened->ao(r);
    EXPECT_EQ(*soup->ao(r), expected);
    EXPECT_EQ(*indexed->ao(r), expected);
  }
}

TEST(ApiCpp, TransformPlacesTheMesh) {
  // A 2 x 2 one-sided quad facing down, placed 0.25 above the origin by the transform.
  const float corners[] = {-1, 0, -1, 1, 0, -1, 1, 0, 1, -1, 0, 1};
  const std::uint32_t quad[] = {0, 2, 1, 0, 3, 2};  // counter-clockwise seen from +Y: faces up
  const std::uint8_t one_sided[] = {0, 0};
  const float lift[12] = {1, 0, 0, 0, 0, 1, 0, 0.25f, 0, 0, 1, 0};
  Mesh mesh;
  mesh.vertices = corners;
  mesh.vertex_count = 4;
  mesh.indices = quad;
  mesh.triangle_count = 2;
  mesh.two_sided = one_sided;
  mesh.transform = lift;
  Options o;
  o.radius = 0.5f;
  o.samples = 256;
  o.origin_offset = 0.0f;
  o.mask_mode = MaskMode::Exact;
  Result<Engine> engine = Engine::build(mesh, o);
  ASSERT_TRUE(engine) << engine.error().message;
  EXPECT_FLOAT_EQ(engine->info().bounds_lo.y, 0.25f);
  // From below, rays meet the quad's back face: one-sided, it blocks nothing.
  EXPECT_EQ(*engine->ao({0, 0, 0}, {0, 1, 0}, 1), 1.0f);
  // From above, looking down at its front face: blocked up to (h/r)^2 = 0.25 open.
  o.sidedness = Sidedness::Two;
  Result<Engine> two = Engine::build(mesh, o);
  ASSERT_TRUE(two);
  double sum = 0.0;
  for (std::uint64_t k = 0; k < 32; ++k) sum += *two->ao({0, 0, 0}, {0, 1, 0}, k);
  EXPECT_NEAR(sum / 32.0, 0.25, 0.02);
  EXPECT_EQ(*engine->ao({0, 0.5f, 0}, {0, -1, 0}, 1), *two->ao({0, 0.5f, 0}, {0, -1, 0}, 1));
}

// --- Threads --------------------------------------------------------------------------------

void expect_concurrent_queries_match(Backend backend, int threads, std::size_t count) {
  Options o;
  o.samples = 128;
  o.radius = 0.8f;
  o.backend = backend;
  o.threads = 2;
  Result<Engine> built = Engine::open("room", o);
  ASSERT_TRUE(built) << built.error().message;
  const Engine& engine = *built;
  Result<SceneData> scene = load_scene("room");
  const std::vector<Receiver> receivers = surface_receivers(*scene, count, 11);

  // One thread, single queries: the reference.
  std::vector<RayMask> reference(receivers.size());
  for (std::size_t i = 0; i < receivers.size(); ++i) reference[i] = *engine.mask(receivers[i]);

  // Many threads at once on the same engine, each in its own order, mixing every query kind.
  std::vector<int> mismatches(static_cast<std::size_t>(threads), 0);
  std::vector<std::thread> pool;
  for (int t = 0; t < threads; ++t) {
    pool.emplace_back([&, t] {
      int& bad = mismatches[static_cast<std::size_t>(t)];
      std::vector<ShadowRay> rays(128);
      for (std::size_t k = 0; k < receivers.size(); ++k) {
        const std::size_t i = (k * 7 + static_cast<std::size_t>(t) * 131) % receivers.size();
        Result<float> ao = engine.ao(receivers[i]);
        Result<RayMask> mask = engine.mask(receivers[i], rays);
        bad += !ao || *ao != reference[i].ao();
        bad += !mask || mask->words != reference[i].words;
      }
      if (t % 2 == 0) {  // and batches, which run on the engine's arena, concurrently too
        std::vector<std::uint64_t> words(receivers.size() * engine.mask_words());
        bad += !engine.masks(receivers, words);
        for (std::size_t i = 0; i < receivers.size(); ++i) {
          for (std::size_t w = 0; w < engine.mask_words(); ++w) bad += words[i * engine.mask_words() + w] != reference[i].words[w];
        }
      }
    });
  }
  for (std::thread& thread : pool) thread.join();
  for (int t = 0; t < threads; ++t) EXPECT_EQ(mismatches[static_cast<std::size_t>(t)], 0) << "thread " << t;
}

TEST(ApiCpp, ConcurrentQueriesEqualSingleThreadedBvh) { expect_concurrent_queries_match(Backend::Bvh, 8, 1500); }
TEST(ApiCpp, ConcurrentQueriesEqualSingleThreadedBrute) { expect_concurrent_queries_match(Backend::Brute, 6, 200); }
TEST(ApiCpp, ConcurrentQueriesEqualSingleThreadedEmbree) { expect_concurrent_queries_match(Backend::Embree, 6, 300); }

TEST(ApiCpp, ProgressAndStats) {
  Options o;
  o.samples = 64;
  Result<Engine> engine = Engine::open("room", o);
  ASSERT_TRUE(engine);
  const std::vector<Receiver> receivers = surface_receivers(*load_scene("room"), 1000, 5);
  std::vector<float> ao(receivers.size());
  std::atomic<std::size_t> last{0};
  WorkStats stats;
  BatchOptions batch;
  batch.progress = [&](std::size_t done, std::size_t total) {
    EXPECT_EQ(total, receivers.size());
    std::size_t seen = last.load();
    while (done > seen && !last.compare_exchange_weak(seen, done)) {
    }
    return true;
  };
  batch.stats = &stats;
  ASSERT_TRUE(engine->ao(receivers, ao, batch));
  EXPECT_EQ(last.load(), receivers.size());
  EXPECT_EQ(stats.receivers, receivers.size());
  EXPECT_GT(stats.triangles_tested, 0u);
  // A throwing callback ends the batch with its own code and the exception's message (it was
  // InternalError, "a bug in exao").
  batch.progress = [](std::size_t, std::size_t) -> bool { throw std::runtime_error("the user's own reason"); };
  const Status stopped = engine->ao(receivers, ao, batch);
  ASSERT_FALSE(stopped);
  EXPECT_EQ(stopped.code(), StatusCode::CallbackError) << stopped.error().message;
  EXPECT_NE(stopped.error().message.find("the user's own reason"), std::string::npos) << stopped.error().message;
}

// progress cancels by returning false, and the batch says so with its own code; the calls stop.
TEST(ApiCpp, ProgressCancelsByItsReturnValue) {
  Options o;
  o.samples = 64;
  o.threads = 2;
  Result<Engine> engine = Engine::open("room", o);
  ASSERT_TRUE(engine);
  // Enough receivers for many progress calls (one per task of a few dozen receivers).
  const std::vector<Receiver> receivers = surface_receivers(*load_scene("room"), 20000, 9);
  std::vector<float> ao(receivers.size());
  std::atomic<int> calls{0};
  BatchOptions batch;
  batch.progress = [&](std::size_t, std::size_t) { return ++calls < 3; };
  const Status cancelled = engine->ao(receivers, ao, batch);
  ASSERT_FALSE(cancelled);
  EXPECT_EQ(cancelled.code(), StatusCode::Cancelled) << cancelled.error().message;
  EXPECT_NE(cancelled.error().message.find("batch.progress"), std::string::npos) << cancelled.error().message;
  // Stopped early: far fewer calls than a whole batch makes (hundreds).
  const int after_cancel = calls.load();
  calls = -1000000;  // a whole batch now runs
  ASSERT_TRUE(engine->ao(receivers, ao, batch));
  EXPECT_LT(after_cancel, calls.load() + 1000000);
}

// One bad receiver gets NaN and its code; every other is computed, the same as without it.
TEST(ApiCpp, ABadReceiverDoesNotFailTheBatch) {
  Options o;
  o.samples = 64;
  Result<Engine> engine = Engine::open("room", o);
  ASSERT_TRUE(engine);
  std::vector<Receiver> receivers = surface_receivers(*load_scene("room"), 500, 4);
  std::vector<float> clean(receivers.size());
  ASSERT_TRUE(engine->ao(receivers, clean));
  receivers[17].position.x = std::numeric_limits<float>::quiet_NaN();
  receivers[300].normal = {0, 0, 0};
  std::vector<float> ao(receivers.size(), -1.0f);
  std::vector<StatusCode> statuses(receivers.size(), StatusCode::InternalError);
  BatchOptions batch;
  batch.statuses = statuses;
  const Status status = engine->ao(receivers, ao, batch);
  ASSERT_FALSE(status);
  EXPECT_EQ(status.code(), StatusCode::InvalidArgument);
  EXPECT_NE(status.error().message.find("receivers[17]"), std::string::npos) << status.error().message;
  EXPECT_NE(status.error().message.find("2 of 500"), std::string::npos) << status.error().message;
  for (std::size_t i = 0; i < receivers.size(); ++i) {
    if (i == 17 || i == 300) {
      EXPECT_TRUE(std::isnan(ao[i])) << i;
      EXPECT_EQ(statuses[i], StatusCode::InvalidArgument) << i;
    } else {
      EXPECT_EQ(ao[i], clean[i]) << i;
      EXPECT_EQ(statuses[i], StatusCode::Ok) << i;
    }
  }
  // Masks too: the bad receivers' words are zero, the others' equal a clean batch's.
  std::vector<std::uint64_t> words(receivers.size() * engine->mask_words(), ~std::uint64_t{0});
  EXPECT_EQ(engine->masks(receivers, words).code(), StatusCode::InvalidArgument);
  for (std::size_t w = 0; w < engine->mask_words(); ++w) EXPECT_EQ(words[17 * engine->mask_words() + w], 0u);
  for (std::size_t i = 0; i < receivers.size(); ++i) {
    int blocked = 0;
    for (std::size_t w = 0; w < engine->mask_words(); ++w) blocked += std::popcount(words[i * engine->mask_words() + w]);
    if (i != 17 && i != 300) {
      EXPECT_EQ(1.0f - static_cast<float>(blocked) / 64.0f, clean[i]) << i;
    }
  }
  std::vector<StatusCode> wrong_size(3);
  batch.statuses = wrong_size;
  EXPECT_EQ(engine->ao(receivers, ao, batch).code(), StatusCode::InvalidArgument);
}

}  // namespace
}  // namespace exao::api

namespace exao::api {
namespace {

// Per-call settings (issue 22): an engine derived with another radius, offset and N over the
// same scene gives the bits of an engine built from scratch with them, leaves its source as it
// was, outlives it, and names its bad settings.
TEST(ApiCpp, WithSettingsEqualsAFreshEngine) {
  Options o;
  o.samples = 64;
  o.radius = 0.5f;
  std::optional<Engine> base;
  {
    Result<Engine> built = Engine::open("room", o);
    ASSERT_TRUE(built) << built.error().message;
    base.emplace(std::move(*built));
  }
  const std::vector<Receiver> receivers = surface_receivers(*load_scene("room"), 400, 11);
  std::vector<float> before(receivers.size());
  ASSERT_TRUE(base->ao(receivers, before));

  QuerySettings settings;
  settings.radius = 1.25f;
  settings.samples = 128;
  settings.origin_offset = 0.002f;
  Result<Engine> derived = base->with_settings(settings);
  ASSERT_TRUE(derived) << derived.error().message;
  EXPECT_EQ(derived->info().radius, 1.25f);
  EXPECT_EQ(derived->info().samples, 128);
  EXPECT_EQ(derived->info().origin_offset, 0.002f);
  EXPECT_EQ(derived->info().triangles, base->info().triangles);

  Options fresh_options = o;
  fresh_options.radius = 1.25f;
  fresh_options.samples = 128;
  fresh_options.origin_offset = 0.002f;
  Result<Engine> fresh = Engine::open("room", fresh_options);
  ASSERT_TRUE(fresh) << fresh.error().message;
  std::vector<float> want(receivers.size()), got(receivers.size()), again(receivers.size());
  ASSERT_TRUE(fresh->ao(receivers, want));
  ASSERT_TRUE(derived->ao(receivers, got));
  EXPECT_EQ(got, want);
  ASSERT_TRUE(base->ao(receivers, again));
  EXPECT_EQ(again, before) << "the source engine changed";

  base.reset();  // the derived engine shares the scene, and keeps it alive
  ASSERT_TRUE(derived->ao(receivers, got));
  EXPECT_EQ(got, want);
  EXPECT_EQ(*derived->ao(receivers[3]), want[3]);

  QuerySettings bad;
  bad.samples = 33;
  const Result<Engine> bad_samples = derived->with_settings(bad);
  ASSERT_FALSE(bad_samples);
  EXPECT_NE(bad_samples.error().message.find("settings.samples"), std::string::npos) << bad_samples.error().message;
  bad = {};
  bad.radius = 0.0f;
  const Result<Engine> bad_radius = derived->with_settings(bad);
  ASSERT_FALSE(bad_radius);
  EXPECT_EQ(bad_radius.code(), StatusCode::InvalidArgument);
  EXPECT_NE(bad_radius.error().message.find("settings.radius"), std::string::npos) << bad_radius.error().message;
}

}  // namespace
}  // namespace exao::api
