// The public API's single-point queries (exao::api::Engine::ao) from several threads at once,
// against the loop a renderer writes without exao: N rtcOccluded rays per shading point, cast
// by the caller with Embree (one at a time, and in packets of 16 rays of the point). Scene: the
// built-in room, or the scene the environment variable EXAO_BENCH_SCENE names (a built-in or a
// file), all triangles two-sided (so that a plain Embree scene, no back-face filter, computes
// the same AO), r = 1% and 5% of the scene's diagonal, N = 64 and 256. Each iteration is one shading point: the next
// of 4096 points on the room's surfaces, in random order (a renderer's bounce and reflection
// points are not coherent). items_per_second is shading points per second, over all threads;
// `rays` is N x that.
//
//   build/tests/benchmarks/api_benchmark [--benchmark_filter=...]

#include <benchmark/benchmark.h>
#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <cstdint>
#include <map>
#include <utility>
#include <memory>
#include <mutex>
#include <random>
#include <vector>

#include "exao/exao.hpp"

namespace {

namespace api = exao::api;

constexpr std::size_t kPoints = 4096;  // a power of two

struct EmbreeScene {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  explicit EmbreeScene(const api::SceneData& data) {
    device = rtcNewDevice(nullptr);
    scene = rtcNewScene(device);
    rtcSetSceneBuildQuality(scene, RTC_BUILD_QUALITY_HIGH);
    const std::size_t n = data.triangle_count();
    RTCGeometry mesh = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(mesh, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                          3 * sizeof(float), 3 * n));
    auto* index = static_cast<unsigned*>(rtcSetNewGeometryBuffer(mesh, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                 3 * sizeof(unsigned), n));
    std::memcpy(v, data.positions.data(), data.positions.size() * sizeof(float));
    for (unsigned i = 0; i < 3 * n; ++i) index[i] = i;
    rtcSetGeometryBuildQuality(mesh, RTC_BUILD_QUALITY_HIGH);
    rtcCommitGeometry(mesh);
    rtcAttachGeometry(scene, mesh);
    rtcReleaseGeometry(mesh);
    rtcCommitScene(scene);
  }
  ~EmbreeScene() {
    rtcReleaseScene(scene);
    rtcReleaseDevice(device);
  }
};

// Everything one N needs, built once and shared by every thread.
struct Workload {
  std::unique_ptr<api::Engine> lut, exact, automatic;  // bvh with each mask mode; auto (the default)
  std::unique_ptr<EmbreeScene> embree;
  std::vector<api::Receiver> points;
  // The caller's own rays: per point, the origin and N world directions and lengths (the
  // engine's rays, so that both sides compute the same AO; a renderer would make its own).
  std::vector<api::Vec3> origins;
  std::vector<api::ShadowRay> rays;  // kPoints x N
  int samples = 0;
  double same_ao = 0.0;  // share of points where exact-mode exao and the Embree loop give the same AO
};

// The diagonal of the scene's bounding box.
float diagonal_of(const api::SceneData& scene) {
  float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  for (std::size_t i = 0; i < scene.positions.size(); ++i) {
    lo[i % 3] = std::min(lo[i % 3], scene.positions[i]);
    hi[i % 3] = std::max(hi[i % 3], scene.positions[i]);
  }
  return std::sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) + (hi[2] - lo[2]) * (hi[2] - lo[2]));
}

const Workload& workload(int samples, float radius_permille) {
  static std::mutex mutex;
  static std::map<std::pair<int, float>, std::unique_ptr<Workload>> cache;
  const std::lock_guard lock(mutex);
  std::unique_ptr<Workload>& w = cache[{samples, radius_permille}];
  if (w) return *w;
  w = std::make_unique<Workload>();
  w->samples = samples;
  const char* named = std::getenv("EXAO_BENCH_SCENE");
  api::Result<api::SceneData> scene = api::load_scene(named && *named ? named : "room");
  if (!scene) {
    std::fprintf(stderr, "api_benchmark: %s\n", scene.error().message.c_str());
    std::exit(1);
  }
  api::Options options;
  options.samples = samples;
  options.radius = radius_permille * 1e-3f * diagonal_of(*scene);
  options.sidedness = api::Sidedness::Two;
  w->automatic = std::make_unique<api::Engine>(std::move(*api::Engine::build(scene->mesh(), options)));
  options.backend = api::Backend::Bvh;  // the paper's method alone, with each mask mode
  options.mask_mode = api::MaskMode::Lut;
  w->lut = std::make_unique<api::Engine>(std::move(*api::Engine::build(scene->mesh(), options)));
  options.mask_mode = api::MaskMode::Exact;
  w->exact = std::make_unique<api::Engine>(std::move(*api::Engine::build(scene->mesh(), options)));
  w->embree = std::make_unique<EmbreeScene>(*scene);

  std::mt19937_64 rng(1);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  w->origins.resize(kPoints);
  w->rays.resize(kPoints * static_cast<std::size_t>(samples));
  for (std::size_t i = 0; i < kPoints; ++i) {
    const std::size_t t = rng() % scene->triangle_count();
    const float* p = scene->positions.data() + 9 * t;
    float u = unit(rng), v = unit(rng);
    if (u + v > 1.0f) u = 1.0f - u, v = 1.0f - v;
    const api::Vec3 a{p[0], p[1], p[2]}, e1{p[3] - p[0], p[4] - p[1], p[5] - p[2]}, e2{p[6] - p[0], p[7] - p[1], p[8] - p[2]};
    const api::Vec3 position{a.x + u * e1.x + v * e2.x, a.y + u * e1.y + v * e2.y, a.z + u * e1.z + v * e2.z};
    const api::Vec3 normal{e1.y * e2.z - e1.z * e2.y, e1.z * e2.x - e1.x * e2.z, e1.x * e2.y - e1.y * e2.x};
    w->points.push_back({position, normal, i});
    (void)w->lut->rays(w->points.back(), w->origins[i],
                       std::span<api::ShadowRay>(w->rays.data() + i * static_cast<std::size_t>(samples), static_cast<std::size_t>(samples)));
  }
  // Both sides compute the same AO (exact masks: only rays grazing an edge may differ).
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  std::size_t same = 0;
  for (std::size_t i = 0; i < kPoints; ++i) {
    int blocked = 0;
    for (int s = 0; s < samples; ++s) {
      const api::ShadowRay& r = w->rays[i * static_cast<std::size_t>(samples) + static_cast<std::size_t>(s)];
      RTCRay ray{w->origins[i].x, w->origins[i].y, w->origins[i].z, 0.0f, r.direction.x, r.direction.y, r.direction.z,
                 0.0f, r.length, 0xFFFFFFFFu, 0, 0};
      rtcOccluded1(w->embree->scene, &context, &ray);
      blocked += ray.tfar == -std::numeric_limits<float>::infinity();
    }
    same += w->exact->ao(w->points[i]).value_or(-1.0f) == 1.0f - static_cast<float>(blocked) / static_cast<float>(samples);
  }
  w->same_ao = static_cast<double>(same) / static_cast<double>(kPoints);
  return *w;
}

// The radius of a run: its second argument, in thousandths of the scene's diagonal.
float radius_of(const benchmark::State& state) { return static_cast<float>(state.range(1)); }

// Point k of a thread: threads walk the points in different orders.
std::size_t point_index(std::size_t k, int thread) {
  return (k * 2654435761u + static_cast<std::size_t>(thread) * 977u) & (kPoints - 1);
}

void report(benchmark::State& state, int samples) {
  state.SetItemsProcessed(state.iterations());
  state.counters["rays"] = benchmark::Counter(static_cast<double>(state.iterations()) * samples, benchmark::Counter::kIsRate);
}

// exao: one call per shading point.
enum class Variant { Lut, Exact, Auto };

void BM_ExaoAo(benchmark::State& state, Variant variant) {
  const int samples = static_cast<int>(state.range(0));
  const Workload& w = workload(samples, radius_of(state));
  const api::Engine& engine = variant == Variant::Auto ? *w.automatic : variant == Variant::Exact ? *w.exact : *w.lut;
  std::size_t k = 0;
  float sum = 0.0f;
  for (auto _ : state) {
    sum += engine.ao(w.points[point_index(k++, state.thread_index())]).value_or(0.0f);
  }
  benchmark::DoNotOptimize(sum);
  report(state, samples);
  state.counters["same_ao"] = benchmark::Counter(w.same_ao, benchmark::Counter::kAvgThreads);
}

// The caller's loop: N rtcOccluded1 rays per shading point.
void BM_EmbreeOccluded1(benchmark::State& state) {
  const int samples = static_cast<int>(state.range(0));
  const Workload& w = workload(samples, radius_of(state));
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  std::size_t k = 0;
  float sum = 0.0f;
  for (auto _ : state) {
    const std::size_t i = point_index(k++, state.thread_index());
    const api::Vec3 o = w.origins[i];
    const api::ShadowRay* rays = w.rays.data() + i * static_cast<std::size_t>(samples);
    int blocked = 0;
    for (int s = 0; s < samples; ++s) {
      RTCRay ray{o.x, o.y, o.z, 0.0f, rays[s].direction.x, rays[s].direction.y, rays[s].direction.z, 0.0f,
                 rays[s].length, 0xFFFFFFFFu, 0, 0};
      rtcOccluded1(w.embree->scene, &context, &ray);
      blocked += ray.tfar == -std::numeric_limits<float>::infinity();
    }
    sum += 1.0f - static_cast<float>(blocked) / static_cast<float>(samples);
  }
  benchmark::DoNotOptimize(sum);
  report(state, samples);
}

// The caller's loop with packets: the N rays of the point, 16 at a time (rtcOccluded16).
void BM_EmbreeOccluded16(benchmark::State& state) {
  const int samples = static_cast<int>(state.range(0));
  const Workload& w = workload(samples, radius_of(state));
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  alignas(64) RTCRay16 packet;
  alignas(64) int valid[16];
  for (int& v : valid) v = -1;
  std::size_t k = 0;
  float sum = 0.0f;
  for (auto _ : state) {
    const std::size_t i = point_index(k++, state.thread_index());
    const api::Vec3 o = w.origins[i];
    const api::ShadowRay* rays = w.rays.data() + i * static_cast<std::size_t>(samples);
    int blocked = 0;
    for (int first = 0; first < samples; first += 16) {
      for (int lane = 0; lane < 16; ++lane) {
        const api::ShadowRay& r = rays[first + lane];
        packet.org_x[lane] = o.x, packet.org_y[lane] = o.y, packet.org_z[lane] = o.z;
        packet.dir_x[lane] = r.direction.x, packet.dir_y[lane] = r.direction.y, packet.dir_z[lane] = r.direction.z;
        packet.tnear[lane] = 0.0f, packet.tfar[lane] = r.length, packet.time[lane] = 0.0f;
        packet.mask[lane] = 0xFFFFFFFFu, packet.id[lane] = 0, packet.flags[lane] = 0;
      }
      rtcOccluded16(valid, w.embree->scene, &context, &packet);
      for (int lane = 0; lane < 16; ++lane) blocked += packet.tfar[lane] == -std::numeric_limits<float>::infinity();
    }
    sum += 1.0f - static_cast<float>(blocked) / static_cast<float>(samples);
  }
  benchmark::DoNotOptimize(sum);
  report(state, samples);
}

// exao's batch query over all 4096 points per iteration, parallel on the engine's own threads
// (called from one thread): what a renderer gets when it can gather its shading points.
void BM_ExaoBatch(benchmark::State& state) {
  const int samples = static_cast<int>(state.range(0));
  const Workload& w = workload(samples, radius_of(state));
  std::vector<float> ao(kPoints);
  for (auto _ : state) {
    const api::Status ok = w.lut->ao(w.points, ao);
    benchmark::DoNotOptimize(ok.ok());
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(kPoints));
  state.counters["rays"] = benchmark::Counter(static_cast<double>(state.iterations()) * kPoints * samples, benchmark::Counter::kIsRate);
}

void configure(benchmark::internal::Benchmark* b) {
  b->ArgNames({"N", "r_permille"})->ArgsProduct({{64, 256}, {10, 50}})->Threads(1)->Threads(2)->Threads(4)->UseRealTime();
}

BENCHMARK_CAPTURE(BM_ExaoAo, lut, Variant::Lut)->Apply(configure);
BENCHMARK_CAPTURE(BM_ExaoAo, exact, Variant::Exact)->Apply(configure);
BENCHMARK_CAPTURE(BM_ExaoAo, auto, Variant::Auto)->Apply(configure);
BENCHMARK(BM_EmbreeOccluded1)->Apply(configure);
BENCHMARK(BM_EmbreeOccluded16)->Apply(configure);
BENCHMARK(BM_ExaoBatch)->ArgNames({"N", "r_permille"})->ArgsProduct({{64, 256}, {10, 50}})->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
