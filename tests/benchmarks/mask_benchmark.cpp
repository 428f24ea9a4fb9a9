// One triangle's mask, table (lut) against exact, N = 32 ... 1024 (DESIGN.md section 4: "the
// benchmark says which is faster where"). Each iteration takes the next of 4096 random triangles
// near random receivers, so the four table look-ups land on unrelated cells and miss the cache
// as they would in a real scene; every triangle passes the culling tests, so what is timed is
// the mask itself. Also the two parts alone: four plane masks, and one region (sphere) mask;
// and the time to build a table.
//
//   build/tests/benchmarks/mask_benchmark [--benchmark_filter=...]

#include <benchmark/benchmark.h>

#include <cmath>
#include <map>
#include <memory>
#include <utility>
#include <vector>

#include "core/random.h"
#include "core/receiver_frame.h"
#include "core/scene.h"
#include "core/shadow_rays.h"
#include "lut/mask_engine.h"

namespace exao::lut {
namespace {

constexpr std::size_t kCases = 4096;  // a power of two

glm::dvec3 random_unit(Rng& rng) {
  for (;;) {
    const glm::dvec3 v(2.0 * rng.uniform() - 1.0, 2.0 * rng.uniform() - 1.0, 2.0 * rng.uniform() - 1.0);
    const double l = glm::length(v);
    if (l > 0.1 && l <= 1.0) return v / l;
  }
}

// Everything a benchmark of one N needs, built once per N and kept.
struct Workload {
  ShadowRays rays;
  MaskEngine lut, exact;
  TriangleSet triangles;             // kCases triangles, each within reach of its frame
  std::vector<Frame> frames;         // the receiver of each triangle
  std::vector<Plane> planes;         // 4 per case: the triangle's edge and face planes (normalised)
  std::vector<glm::vec3> centres;    // the triangle's sphere centre in its frame
};

Workload& workload(int n) {
  static std::map<int, std::unique_ptr<Workload>> cache;
  auto& slot = cache[n];
  if (slot) return *slot;
  slot = std::make_unique<Workload>();
  Workload& w = *slot;
  auto pattern = make_sample_pattern(n, Falloff::Constant);
  w.rays = *make_shadow_rays(*pattern, 1.0f, 1e-4f);
  w.lut = std::move(*MaskEngine::build(w.rays, MaskMode::Lut));
  w.exact = std::move(*MaskEngine::build(w.rays, MaskMode::Exact));

  Rng rng(static_cast<std::uint64_t>(n));
  Scene scene;
  with_mask_bits(n, [&](auto bits) {
    constexpr int Bits = decltype(bits)::value;
    while (scene.triangle_count() < kCases) {
      Receiver receiver;
      receiver.position =
          glm::vec3(20.0 * rng.uniform() - 10.0, 20.0 * rng.uniform() - 10.0, 20.0 * rng.uniform() - 10.0);
      receiver.normal = glm::vec3(random_unit(rng));
      receiver.key = rng.next();
      const Frame frame = w.rays.frame(receiver);
      // Triangles of 0.02 r to 0.5 r around a point of the upper hemisphere of radius 0.9 r.
      glm::dvec3 middle = random_unit(rng) * (0.9 * rng.uniform());
      middle.z = std::abs(middle.z);
      const double size = 0.02 * std::pow(25.0, rng.uniform());
      glm::vec3 v[3];
      for (glm::vec3& vertex : v) {
        const glm::dvec3 local = middle + size * random_unit(rng);
        vertex = frame.to_world_direction(glm::vec3(local)) + frame.origin;
      }
      Scene one;
      one.add_triangle(v[0], v[1], v[2], true, 0);
      if (one.triangle_count() == 0) continue;
      if (w.exact.triangle_mask<Bits>(TriangleSet::build(one), 0, frame).none()) continue;  // culled
      scene.add_triangle(v[0], v[1], v[2], true, 0);
      w.frames.push_back(frame);
      // The four planes as triangle_mask builds them.
      glm::vec3 a = frame.to_local(v[0]), b = frame.to_local(v[1]), c = frame.to_local(v[2]);
      const glm::vec3 normal = glm::normalize(glm::cross(b - a, c - a));
      const float sd = glm::dot(normal, a);
      const float sign = sd > 0.0f ? 1.0f : -1.0f;
      w.planes.push_back({glm::normalize(glm::cross(a, b)) * sign, 0.0f});
      w.planes.push_back({glm::normalize(glm::cross(b, c)) * sign, 0.0f});
      w.planes.push_back({glm::normalize(glm::cross(c, a)) * sign, 0.0f});
      w.planes.push_back({normal * sign, std::abs(sd)});
    }
  });
  w.triangles = TriangleSet::build(scene);
  for (std::size_t t = 0; t < kCases; ++t) w.centres.push_back(w.frames[t].to_local(w.triangles.centre[t]));
  return w;
}

// The whole triangle_mask: culling tests, planes, region clip.
void triangle_mask(benchmark::State& state, MaskMode mode) {
  const int n = static_cast<int>(state.range(0));
  Workload& w = workload(n);
  const MaskEngine& engine = mode == MaskMode::Lut ? w.lut : w.exact;
  with_mask_bits(n, [&](auto bits) {
    constexpr int Bits = decltype(bits)::value;
    std::size_t i = 0;
    Mask<Bits> acc;
    for (auto _ : state) {
      acc |= engine.triangle_mask<Bits>(w.triangles, static_cast<std::uint32_t>(i), w.frames[i]);
      i = (i + 1) & (kCases - 1);
    }
    benchmark::DoNotOptimize(acc);
  });
  state.SetItemsProcessed(state.iterations());
  state.counters["table_MiB"] = static_cast<double>(engine.table_bytes()) / (1024.0 * 1024.0);
}

// Only the four plane masks AND-ed (no culling, no region clip).
void four_planes(benchmark::State& state, MaskMode mode) {
  const int n = static_cast<int>(state.range(0));
  Workload& w = workload(n);
  const MaskEngine& engine = mode == MaskMode::Lut ? w.lut : w.exact;
  with_mask_bits(n, [&](auto bits) {
    constexpr int Bits = decltype(bits)::value;
    std::size_t i = 0;
    Mask<Bits> acc;
    for (auto _ : state) {
      const Plane* p = &w.planes[4 * i];
      Mask<Bits> m = engine.plane_mask<Bits>(p[0]);
      m &= engine.plane_mask<Bits>(p[1]);
      m &= engine.plane_mask<Bits>(p[2]);
      m &= engine.plane_mask<Bits>(p[3]);
      acc |= m;
      i = (i + 1) & (kCases - 1);
    }
    benchmark::DoNotOptimize(acc);
  });
  state.SetItemsProcessed(state.iterations());
}

// One region mask of a triangle's sphere (the BVH's per-node cost).
void region_mask(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  Workload& w = workload(n);
  with_mask_bits(n, [&](auto bits) {
    constexpr int Bits = decltype(bits)::value;
    std::size_t i = 0;
    Mask<Bits> acc;
    for (auto _ : state) {
      acc |= w.exact.region_mask<Bits>(w.centres[i], w.triangles.radius[i], kNodeMargin);
      i = (i + 1) & (kCases - 1);
    }
    benchmark::DoNotOptimize(acc);
  });
  state.SetItemsProcessed(state.iterations());
}

// Building the points table at the default resolution, on all threads.
void table_build(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const SamplePattern& pattern = workload(n).rays.pattern;
  std::size_t bytes = 0;
  for (auto _ : state) {
    auto table = PlaneTable::build(pattern, TableKind::Points);
    bytes = table->memory_bytes();
    benchmark::DoNotOptimize(table);
  }
  state.counters["table_MiB"] = static_cast<double>(bytes) / (1024.0 * 1024.0);
}

void sizes(benchmark::internal::Benchmark* b) {
  for (const int n : {32, 64, 128, 256, 512, 1024}) b->Arg(n);
}

BENCHMARK_CAPTURE(triangle_mask, lut, MaskMode::Lut)->Apply(sizes);
BENCHMARK_CAPTURE(triangle_mask, exact, MaskMode::Exact)->Apply(sizes);
BENCHMARK_CAPTURE(four_planes, lut, MaskMode::Lut)->Apply(sizes);
BENCHMARK_CAPTURE(four_planes, exact, MaskMode::Exact)->Apply(sizes);
BENCHMARK(region_mask)->Apply(sizes);
BENCHMARK(table_build)->Apply(sizes)->Unit(benchmark::kMillisecond)->Iterations(2);

}  // namespace
}  // namespace exao::lut

BENCHMARK_MAIN();
