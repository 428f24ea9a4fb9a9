// Bad arguments to the public C++ API are returned errors with the right code and a message
// naming the argument: never an exception, a print or a crash.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "exao/exao.hpp"

namespace exao::api {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

template <class R>
void expect_error(const R& result, StatusCode code, const std::string& names) {
  ASSERT_FALSE(result) << "expected an error naming " << names;
  EXPECT_EQ(result.code(), code) << result.error().message;
  EXPECT_NE(result.error().message.find(names), std::string::npos) << result.error().message;
  EXPECT_EQ(result.error().message.find('\n'), std::string::npos) << "one line";
}

// One triangle, two-sided, under which queries are made.
struct Triangle {
  float vertices[9] = {-1, 1, -1, 1, 1, -1, 0, 1, 1};
  Mesh mesh() const {
    Mesh m;
    m.vertices = vertices;
    m.vertex_count = 3;
    m.triangle_count = 1;
    return m;
  }
};

Options small() {
  Options o;
  o.samples = 32;
  o.radius = 2.0f;
  o.mask_mode = MaskMode::Exact;
  return o;
}

TEST(ApiErrors, BadOptions) {
  const Triangle tri;
  const auto with = [&](auto change) {
    Options o = small();
    change(o);
    return Engine::build(tri.mesh(), o);
  };
  expect_error(with([](Options& o) { o.samples = 0; }), StatusCode::InvalidArgument, "options.samples");
  expect_error(with([](Options& o) { o.samples = 100; }), StatusCode::InvalidArgument, "100");
  expect_error(with([](Options& o) { o.samples = 2048; }), StatusCode::InvalidArgument, "options.samples");
  expect_error(with([](Options& o) { o.samples = -32; }), StatusCode::InvalidArgument, "options.samples");
  expect_error(with([](Options& o) { o.radius = 0.0f; }), StatusCode::InvalidArgument, "options.radius");
  expect_error(with([](Options& o) { o.radius = -1.0f; }), StatusCode::InvalidArgument, "options.radius");
  expect_error(with([](Options& o) { o.radius = kNaN; }), StatusCode::InvalidArgument, "options.radius");
  expect_error(with([](Options& o) { o.radius = kInf; }), StatusCode::InvalidArgument, "options.radius");
  expect_error(with([](Options& o) { o.origin_offset = -0.1f; }), StatusCode::InvalidArgument, "options.origin_offset");
  expect_error(with([](Options& o) { o.origin_offset = kNaN; }), StatusCode::InvalidArgument, "options.origin_offset");
  expect_error(with([](Options& o) { o.threads = -1; }), StatusCode::InvalidArgument, "options.threads");
  expect_error(with([](Options& o) { o.table_resolution = 2; }), StatusCode::InvalidArgument, "options.table_resolution");
  expect_error(with([](Options& o) { o.table_resolution = 1000; }), StatusCode::InvalidArgument, "options.table_resolution");
  expect_error(with([](Options& o) { o.bvh_branching = 3; }), StatusCode::InvalidArgument, "options.bvh_branching");
  expect_error(with([](Options& o) { o.backend = static_cast<Backend>(7); }), StatusCode::InvalidArgument, "options.backend");
  expect_error(with([](Options& o) { o.falloff = static_cast<Falloff>(-1); }), StatusCode::InvalidArgument, "options.falloff");
  expect_error(with([](Options& o) { o.mask_mode = static_cast<MaskMode>(2); }), StatusCode::InvalidArgument, "options.mask_mode");
  expect_error(with([](Options& o) { o.sidedness = static_cast<Sidedness>(3); }), StatusCode::InvalidArgument, "options.sidedness");
  expect_error(with([](Options& o) { o.embree_rays = static_cast<EmbreeRays>(9); }), StatusCode::InvalidArgument, "options.embree_rays");
  EXPECT_TRUE(with([](Options&) {}));
}

TEST(ApiErrors, BadMeshes) {
  const Triangle tri;
  const Options o = small();
  const auto with = [&](auto change) {
    Mesh m = tri.mesh();
    change(m);
    return Engine::build(m, o);
  };
  expect_error(Engine::build(std::span<const Mesh>(), o), StatusCode::InvalidArgument, "meshes");
  expect_error(with([](Mesh& m) { m.vertices = nullptr; }), StatusCode::InvalidArgument, "meshes[0].vertices");
  expect_error(with([](Mesh& m) { m.vertex_stride = 8; }), StatusCode::InvalidArgument, "meshes[0].vertex_stride");
  expect_error(with([](Mesh& m) { m.vertex_stride = 13; }), StatusCode::InvalidArgument, "meshes[0].vertex_stride");
  expect_error(with([](Mesh& m) { m.triangle_count = 2; }), StatusCode::InvalidArgument, "triangle_count");
  expect_error(with([](Mesh& m) { m.triangle_count = 0; }), StatusCode::InvalidArgument, "no triangle");
  const std::uint32_t out_of_range[] = {0, 1, 3};
  expect_error(with([&](Mesh& m) { m.indices = out_of_range; }), StatusCode::InvalidArgument, "vertex 3");
  const std::uint32_t fine[] = {0, 1, 2};
  expect_error(with([&](Mesh& m) { m.indices = fine; m.index_stride = 4; }), StatusCode::InvalidArgument, "index_stride");
  const float nan_transform[12] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, kNaN};
  expect_error(with([&](Mesh& m) { m.transform = nan_transform; }), StatusCode::InvalidArgument, "transform");

  Triangle nan_vertex;
  nan_vertex.vertices[4] = kNaN;
  expect_error(Engine::build(nan_vertex.mesh(), o), StatusCode::InvalidArgument, "non-finite vertex");
  Triangle collinear;
  collinear.vertices[6] = 3.0f, collinear.vertices[7] = 1.0f, collinear.vertices[8] = -1.0f;  // on the first edge's line
  expect_error(Engine::build(collinear.mesh(), o), StatusCode::InvalidArgument, "no triangle of non-zero area");

  // A zero-area triangle beside a good one is dropped and counted, not an error.
  const float two[] = {-1, 1, -1, 1, 1, -1, 0, 1, 1, 0, 0, 0, 0, 0, 0, 1, 1, 1};
  Mesh both;
  both.vertices = two;
  both.vertex_count = 6;
  both.triangle_count = 2;
  Result<Engine> engine = Engine::build(both, o);
  ASSERT_TRUE(engine) << engine.error().message;
  EXPECT_EQ(engine->info().triangles, 1u);
  EXPECT_EQ(engine->info().zero_area_skipped, 1u);
}

TEST(ApiErrors, BadFiles) {
  expect_error(Engine::open("/nonexistent/scene.glb", small()), StatusCode::FileError, "/nonexistent/scene.glb");
  expect_error(load_scene("/nonexistent/scene.obj"), StatusCode::FileError, "scene.obj");
  expect_error(load_scene(""), StatusCode::InvalidArgument, "name_or_path");
  expect_error(Engine::open("plane-pair", [] { Options o; o.samples = 48; return o; }()), StatusCode::InvalidArgument, "48");
}

TEST(ApiErrors, BadQueries) {
  const Triangle tri;
  Result<Engine> built = Engine::build(tri.mesh(), small());
  ASSERT_TRUE(built) << built.error().message;
  const Engine& engine = *built;
  expect_error(engine.ao({kNaN, 0, 0}, {0, 1, 0}, 1), StatusCode::InvalidArgument, "position");
  expect_error(engine.ao({0, kInf, 0}, {0, 1, 0}, 1), StatusCode::InvalidArgument, "position");
  expect_error(engine.ao({0, 0, 0}, {0, 0, 0}, 1), StatusCode::InvalidArgument, "normal");
  expect_error(engine.ao({0, 0, 0}, {0, kNaN, 0}, 1), StatusCode::InvalidArgument, "normal");
  expect_error(engine.ao({0, 0, 0}, {1e-30f, 0, 0}, 1), StatusCode::InvalidArgument, "normal");
  expect_error(engine.ao({0, 0, 0}, {3e38f, 3e38f, 0}, 1), StatusCode::InvalidArgument, "normal");
  expect_error(engine.mask({{kNaN, 0, 0}, {0, 1, 0}, 1}), StatusCode::InvalidArgument, "position");
  std::vector<ShadowRay> rays(31);
  expect_error(engine.mask({{0, 0, 0}, {0, 1, 0}, 1}, rays), StatusCode::InvalidArgument, "rays");
  Vec3 origin;
  expect_error(engine.rays({{0, 0, 0}, {0, 1, 0}, 1}, origin, {}), StatusCode::InvalidArgument, "rays");

  // A valid query still works, and a tiny but normalisable normal is fine.
  Result<float> ao = engine.ao({0, 0, 0}, {0, 1e-10f, 0}, 1);
  ASSERT_TRUE(ao) << ao.error().message;
  EXPECT_LT(*ao, 1.0f);
  EXPECT_GT(*ao, 0.0f);

  // Batches: sizes must match, and a bad receiver is named by index with nothing written.
  std::vector<Receiver> receivers(4, Receiver{{0, 0, 0}, {0, 1, 0}, 0});
  receivers[2].normal = {0, 0, 0};
  std::vector<float> out(4, -7.0f);
  expect_error(engine.ao(receivers, out), StatusCode::InvalidArgument, "receivers[2]");
  for (const float v : out) EXPECT_EQ(v, -7.0f);
  std::vector<float> short_out(3);
  expect_error(engine.ao(receivers, short_out), StatusCode::InvalidArgument, "ao");
  std::vector<std::uint64_t> words(3);
  expect_error(engine.masks(receivers, words), StatusCode::InvalidArgument, "words");
  EXPECT_TRUE(engine.ao({}, {}));
}

TEST(ApiErrors, MovedFromEngineAnswersWithAnError) {
  const Triangle tri;
  Result<Engine> built = Engine::build(tri.mesh(), small());
  ASSERT_TRUE(built);
  Engine engine = std::move(*built);
  Engine other = std::move(engine);
  expect_error(engine.ao({0, 0, 0}, {0, 1, 0}, 1), StatusCode::InvalidArgument, "engine");  // NOLINT: use after move is the test
  std::vector<Receiver> receivers(1, Receiver{});
  std::vector<float> out(1);
  expect_error(engine.ao(receivers, out), StatusCode::InvalidArgument, "engine");
  EXPECT_EQ(engine.samples(), 0);
  EXPECT_TRUE(other.ao({0, 0, 0}, {0, 1, 0}, 1));
}

TEST(ApiErrors, StatusTexts) {
  EXPECT_STREQ(status_text(StatusCode::Ok), "ok");
  EXPECT_STREQ(status_text(StatusCode::InvalidArgument), "invalid argument");
  EXPECT_STREQ(status_text(static_cast<StatusCode>(99)), "unknown status");
  EXPECT_EQ(std::string(version()), std::to_string(kVersionMajor) + "." + std::to_string(kVersionMinor) + "." +
                                        std::to_string(kVersionPatch));
}

}  // namespace
}  // namespace exao::api
