// Bad arguments to the public C++ API are returned errors with the right code and a message
// naming the argument: never an exception, a print or a crash.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
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
  // Enum errors give the value the caller passed (the backend's was remapped to -1 once).
  expect_error(with([](Options& o) { o.backend = static_cast<Backend>(9); }), StatusCode::InvalidArgument, "got 9");
  expect_error(with([](Options& o) { o.backend = static_cast<Backend>(-3); }), StatusCode::InvalidArgument, "got -3");
  expect_error(with([](Options& o) { o.falloff = static_cast<Falloff>(5); }), StatusCode::InvalidArgument, "got 5");
  expect_error(with([](Options& o) { o.mask_mode = static_cast<MaskMode>(6); }), StatusCode::InvalidArgument, "got 6");
  expect_error(with([](Options& o) { o.sidedness = static_cast<Sidedness>(7); }), StatusCode::InvalidArgument, "got 7");
  expect_error(with([](Options& o) { o.embree_rays = static_cast<EmbreeRays>(8); }), StatusCode::InvalidArgument, "got 8");
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
  expect_error(Engine::build(collinear.mesh(), o), StatusCode::InvalidArgument, "1 of zero area");

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

// Vertices beyond +-1e17 (Embree's limit) are dropped: counted, and when nothing is left the
// error says why (it said "no triangle of non-zero area" of a scene of large triangles).
TEST(ApiErrors, DroppedGeometryIsCountedAndExplained) {
  const Options o = small();
  Triangle far;
  far.vertices[0] = 2e17f;
  expect_error(Engine::build(far.mesh(), o), StatusCode::InvalidArgument, "1 with a vertex beyond +-1e17");

  const float two[] = {-1, 1, -1, 1, 1, -1, 0, 1, 1, 3e17f, 0, 0, 0, 0, 0, 1, 1, 1};
  Mesh both;
  both.vertices = two;
  both.vertex_count = 6;
  both.triangle_count = 2;
  Result<Engine> engine = Engine::build(both, o);
  ASSERT_TRUE(engine) << engine.error().message;
  EXPECT_EQ(engine->info().triangles, 1u);
  EXPECT_EQ(engine->info().beyond_limit_skipped, 1u);
  EXPECT_EQ(engine->info().zero_area_skipped, 0u);
}

// value() of an error is loud in every build type (it was an assert: UB, a SIGSEGV in Release).
TEST(ApiErrors, ValueOfAnErrorThrows) {
  const Triangle tri;
  Options o = small();
  o.samples = 33;
  const Result<Engine> failed = Engine::build(tri.mesh(), o);
  ASSERT_FALSE(failed);
  try {
    (void)failed.value();
    ADD_FAILURE() << "value() of an error returned";
  } catch (const BadResultAccess& e) {
    EXPECT_EQ(e.error().code, StatusCode::InvalidArgument);
    EXPECT_NE(std::string(e.what()).find("options.samples"), std::string::npos) << e.what();
  }
  EXPECT_THROW((void)failed->info(), BadResultAccess);
  const Result<float> fine = 0.5f;
  EXPECT_THROW((void)fine.error(), BadResultAccess);
  EXPECT_THROW((void)Status().error(), BadResultAccess);
}

// Run by CTest with EXAO_ISA set (api_errors_isa_*): EngineInfo::simd is the level the kernels
// run (it gave the level the library was compiled for), a bad value is an error naming it, and
// the library prints nothing (it warned on stderr).
TEST(ApiEnvironment, IsaLevel) {
  const char* env = std::getenv("EXAO_ISA");
  if (!env) GTEST_SKIP() << "EXAO_ISA is not set";
  const Triangle tri;
  testing::internal::CaptureStderr();
  const Result<Engine> engine = Engine::build(tri.mesh(), small());
  Options embree = small();
  embree.backend = Backend::Embree;
  const Result<Engine> reference = Engine::build(tri.mesh(), embree);
  const std::string printed = testing::internal::GetCapturedStderr();
  EXPECT_EQ(printed, "") << "the library printed";
  if (std::string(env) == "bogus") {
    expect_error(engine, StatusCode::InvalidArgument, "EXAO_ISA: 'bogus'");
    return;
  }
  ASSERT_TRUE(engine) << engine.error().message;
  EXPECT_STREQ(engine->info().simd, env);
  ASSERT_TRUE(reference) << reference.error().message;
  EXPECT_STREQ(reference->info().simd, "none");
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

  // Batches: sizes must match, and a bad receiver is named by index, gets NaN, and the others
  // are computed.
  std::vector<Receiver> receivers(4, Receiver{{0, 0, 0}, {0, 1, 0}, 0});
  receivers[2].normal = {0, 0, 0};
  std::vector<float> out(4, -7.0f);
  expect_error(engine.ao(receivers, out), StatusCode::InvalidArgument, "receivers[2]");
  for (std::size_t i = 0; i < out.size(); ++i) {
    if (i == 2) {
      EXPECT_TRUE(std::isnan(out[i]));
    } else {
      EXPECT_EQ(out[i], *engine.ao(receivers[i]));
    }
  }
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
