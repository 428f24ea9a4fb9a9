// exao::api::Engine: the public AO engine over the internal modules (core, lut, bvh).
//
// Build: the caller's meshes become one exao::Scene (the only full copy), which the chosen
// backend turns into its own structure (a BVH, a triangle set or an Embree scene); the Scene is
// then dropped. Queries: one receiver on the calling thread, or a batch on the engine's own TBB
// arena. The rays are those of the exao program for the same scene and options, so the bits are
// the same as `exao query`'s (tests/api_cpp_test.cpp checks it).

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/combinable.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>
#include <tbb/task_arena.h>

#include "api/boundary.h"
#include "bvh/bvh.h"
#include "bvh/traverse.h"
#include "core/bounds.h"
#include "core/coordinate_limit.h"
#include "core/embree_reference.h"
#include "core/load_scene.h"
#include "core/mask.h"
#include "core/mask_set.h"
#include "core/progress.h"
#include "core/receiver_frame.h"
#include "core/sample_pattern.h"
#include "core/scene.h"
#include "core/shadow_rays.h"
#include "exao/exao.hpp"
#include "lut/brute.h"
#include "lut/float_mode.h"
#include "lut/mask_engine.h"
#include "lut/plane_table.h"
#include "lut/triangle_set.h"

namespace exao::api {

using detail::guard;
using detail::invalid;

struct Engine::Impl {
  EngineInfo info;
  ShadowRays rays;
  std::optional<lut::MaskEngine> masks;            // bvh, brute
  std::unique_ptr<bvh::Bvh> bvh;                   // bvh
  std::unique_ptr<lut::TriangleSet> triangles;     // brute
  std::unique_ptr<EmbreeScene> embree;             // embree
  std::unique_ptr<tbb::task_arena> arena;          // batch queries and the build
  api::EmbreeRays embree_rays = api::EmbreeRays::Packet16;  // default of embree batches
};

namespace {

const EngineInfo kEmptyInfo{};

[[nodiscard]] bool finite(const Vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

// --- Options ------------------------------------------------------------------------------------

template <class Enum>
[[nodiscard]] bool in_range(Enum value, Enum last) {
  const int v = static_cast<int>(value);
  return v >= 0 && v <= static_cast<int>(last);
}

[[nodiscard]] std::optional<Error> check_options(const Options& o) {
  if (o.radius && !(std::isfinite(*o.radius) && *o.radius > 0.0f)) {
    return invalid("options.radius: must be a finite length > 0, got " + std::to_string(*o.radius));
  }
  if (o.samples < kMinSamples || o.samples > kMaxSamples || o.samples % 32 != 0) {
    return invalid("options.samples: must be a multiple of 32 from 32 to 1024, got " + std::to_string(o.samples));
  }
  if (!in_range(o.falloff, Falloff::Quadratic)) return invalid("options.falloff: not a Falloff value");
  if (!in_range(o.sidedness, Sidedness::Two)) return invalid("options.sidedness: not a Sidedness value");
  if (!in_range(o.mask_mode, MaskMode::Exact)) return invalid("options.mask_mode: not a MaskMode value");
  if (!in_range(o.backend, Backend::Embree)) return invalid("options.backend: not a Backend value");
  if (!in_range(o.embree_rays, EmbreeRays::Packet16)) return invalid("options.embree_rays: not an EmbreeRays value");
  if (o.origin_offset && !(std::isfinite(*o.origin_offset) && *o.origin_offset >= 0.0f)) {
    return invalid("options.origin_offset: must be a finite length >= 0, got " + std::to_string(*o.origin_offset));
  }
  if (o.threads < 0) return invalid("options.threads: must be >= 0 (0: one per core), got " + std::to_string(o.threads));
  if (o.table_resolution != 0 &&
      (o.table_resolution < lut::kMinTableResolution || o.table_resolution > lut::kMaxTableResolution)) {
    return invalid("options.table_resolution: must be 0 or from " + std::to_string(lut::kMinTableResolution) + " to " +
                   std::to_string(lut::kMaxTableResolution) + ", got " + std::to_string(o.table_resolution));
  }
  if (o.bvh_branching != 2 && o.bvh_branching != 4) {
    return invalid("options.bvh_branching: must be 2 or 4, got " + std::to_string(o.bvh_branching));
  }
  return std::nullopt;
}

// --- Meshes -------------------------------------------------------------------------------------

[[nodiscard]] glm::vec3 read_vertex(const Mesh& mesh, std::size_t i) {
  const float* v = reinterpret_cast<const float*>(reinterpret_cast<const unsigned char*>(mesh.vertices) + i * mesh.vertex_stride);
  return {v[0], v[1], v[2]};
}

[[nodiscard]] glm::vec3 place(const float* m, const glm::vec3& v) {
  if (!m) return v;
  return {m[0] * v.x + m[1] * v.y + m[2] * v.z + m[3], m[4] * v.x + m[5] * v.y + m[6] * v.z + m[7],
          m[8] * v.x + m[9] * v.y + m[10] * v.z + m[11]};
}

// Appends mesh k's triangles to `scene`; zero-area ones are dropped (they block no ray in any
// backend) and counted in scene.report.
[[nodiscard]] std::optional<Error> add_mesh(Scene& scene, const Mesh& mesh, std::size_t k) {
  const std::string name = "meshes[" + std::to_string(k) + "]";
  const std::size_t n = mesh.triangle_count;
  if (n == 0) return std::nullopt;
  if (!mesh.vertices) return invalid(name + ".vertices: null with triangle_count " + std::to_string(n));
  if (reinterpret_cast<std::uintptr_t>(mesh.vertices) % alignof(float) != 0) {
    return invalid(name + ".vertices: not 4-byte aligned");
  }
  if (mesh.vertex_stride < 3 * sizeof(float) || mesh.vertex_stride % sizeof(float) != 0) {
    return invalid(name + ".vertex_stride: must be a multiple of 4 and at least 12, got " + std::to_string(mesh.vertex_stride));
  }
  if (mesh.indices) {
    if (reinterpret_cast<std::uintptr_t>(mesh.indices) % alignof(std::uint32_t) != 0) {
      return invalid(name + ".indices: not 4-byte aligned");
    }
    if (mesh.index_stride < 3 * sizeof(std::uint32_t) || mesh.index_stride % sizeof(std::uint32_t) != 0) {
      return invalid(name + ".index_stride: must be a multiple of 4 and at least 12, got " + std::to_string(mesh.index_stride));
    }
  } else if (n > mesh.vertex_count / 3) {
    return invalid(name + ": triangle_count " + std::to_string(n) + " needs " + std::to_string(n) +
                   " x 3 vertices without indices, vertex_count is " + std::to_string(mesh.vertex_count));
  }
  if (mesh.transform) {
    for (int i = 0; i < 12; ++i) {
      if (!std::isfinite(mesh.transform[i])) return invalid(name + ".transform: element " + std::to_string(i) + " is not finite");
    }
  }
  scene.vertices.reserve(scene.vertices.size() + 3 * n);
  scene.two_sided.reserve(scene.two_sided.size() + n);
  scene.material.reserve(scene.material.size() + n);
  for (std::size_t t = 0; t < n; ++t) {
    std::size_t index[3] = {3 * t, 3 * t + 1, 3 * t + 2};
    if (mesh.indices) {
      const auto* row = reinterpret_cast<const std::uint32_t*>(reinterpret_cast<const unsigned char*>(mesh.indices) +
                                                               t * mesh.index_stride);
      for (int j = 0; j < 3; ++j) {
        index[j] = row[j];
        if (index[j] >= mesh.vertex_count) {
          return invalid(name + ": triangle " + std::to_string(t) + " uses vertex " + std::to_string(index[j]) +
                         ", vertex_count is " + std::to_string(mesh.vertex_count));
        }
      }
    }
    glm::vec3 v[3];
    for (int j = 0; j < 3; ++j) {
      v[j] = place(mesh.transform, read_vertex(mesh, index[j]));
      if (!(std::isfinite(v[j].x) && std::isfinite(v[j].y) && std::isfinite(v[j].z))) {
        return invalid(name + ": triangle " + std::to_string(t) + " has a non-finite vertex (" + std::to_string(index[j]) +
                       (mesh.transform ? ", after the transform)" : ")"));
      }
    }
    const bool two = mesh.two_sided ? mesh.two_sided[t] != 0 : true;
    scene.add_triangle(v[0], v[1], v[2], two, -1);
  }
  return std::nullopt;
}

// --- Receivers ----------------------------------------------------------------------------------

// Why a receiver cannot be queried, or nullptr. The frame normalises n: its squared length must
// be a normal float for 1/sqrt to be finite and exact enough.
[[nodiscard]] const char* receiver_problem(const Receiver& r) {
  if (!finite(r.position)) return "position is not finite";
  if (!within_coordinate_limit(glm::vec3(r.position.x, r.position.y, r.position.z))) {
    return "position is beyond +-1e17 (Embree cannot cast rays from there)";
  }
  if (!finite(r.normal)) return "normal is not finite";
  const float len2 = r.normal.x * r.normal.x + r.normal.y * r.normal.y + r.normal.z * r.normal.z;
  if (!(len2 >= FLT_MIN && len2 <= FLT_MAX)) return "normal has zero length (or is too short or long to normalise)";
  return nullptr;
}

[[nodiscard]] exao::Receiver to_internal(const Receiver& r) {
  return {glm::vec3(r.position.x, r.position.y, r.position.z), glm::vec3(r.normal.x, r.normal.y, r.normal.z), r.key};
}

// Spreads the low 21 bits of x to every third bit (a Morton code's one axis).
[[nodiscard]] std::uint64_t spread_bits(std::uint64_t x) {
  x &= 0x1FFFFF;
  x = (x | x << 32) & 0x1F00000000FFFFull;
  x = (x | x << 16) & 0x1F0000FF0000FFull;
  x = (x | x << 8) & 0x100F00F00F00F00Full;
  x = (x | x << 4) & 0x10C30C30C30C30C3ull;
  x = (x | x << 2) & 0x1249249249249249ull;
  return x;
}

// Receivers in Morton order of their positions: neighbours traverse alike, so caches stay warm.
[[nodiscard]] std::vector<std::uint32_t> morton_order(std::span<const exao::Receiver> receivers) {
  Bounds bounds;
  for (const exao::Receiver& r : receivers) bounds.extend(r.position);
  const glm::vec3 scale = glm::vec3(2097151.0f) / glm::max(bounds.extent(), glm::vec3(1e-30f));
  const auto cell = [](float q) -> std::uint64_t {
    return q >= 0.0f ? static_cast<std::uint64_t>(std::min(q, 2097151.0f)) : 0;  // NaN (inf * 0) -> 0
  };
  std::vector<std::pair<std::uint64_t, std::uint32_t>> keyed(receivers.size());
  for (std::size_t i = 0; i < receivers.size(); ++i) {
    const glm::vec3 q = (receivers[i].position - bounds.lo) * scale;
    keyed[i] = {spread_bits(cell(q.x)) | spread_bits(cell(q.y)) << 1 | spread_bits(cell(q.z)) << 2, static_cast<std::uint32_t>(i)};
  }
  tbb::parallel_sort(keyed.begin(), keyed.end());
  std::vector<std::uint32_t> order(receivers.size());
  for (std::size_t i = 0; i < keyed.size(); ++i) order[i] = keyed[i].second;
  return order;
}

[[nodiscard]] exao::EmbreeRays to_internal_rays(api::EmbreeRays rays) {
  switch (rays) {
    case api::EmbreeRays::Single: return exao::EmbreeRays::Single;
    case api::EmbreeRays::Packet4: return exao::EmbreeRays::Packet4;
    case api::EmbreeRays::Packet8: return exao::EmbreeRays::Packet8;
    case api::EmbreeRays::Packet16: return exao::EmbreeRays::Packet16;
  }
  return exao::EmbreeRays::Packet16;
}

[[nodiscard]] exao::Falloff to_internal(api::Falloff falloff) {
  switch (falloff) {
    case api::Falloff::Constant: return exao::Falloff::Constant;
    case api::Falloff::Linear: return exao::Falloff::Linear;
    case api::Falloff::Quadratic: return exao::Falloff::Quadratic;
  }
  return exao::Falloff::Constant;
}

// --- Build --------------------------------------------------------------------------------------

[[nodiscard]] Result<std::unique_ptr<Engine::Impl>> build_impl(Scene& scene, const Options& options,
                                                                std::size_t zero_area_skipped) {
  if (scene.triangle_count() == 0) return invalid("the scene has no triangle of non-zero area");
  if (options.sidedness != Sidedness::Auto) {
    apply_sidedness(scene, options.sidedness == Sidedness::One ? exao::Sidedness::One : exao::Sidedness::Two);
  }
  const Bounds bounds = scene.bounds();
  const float diagonal = bounds.diagonal();
  // The exao program's defaults, computed the same way ("5%" is parsed as 5 * 0.01 * diagonal),
  // so that the same scene gives the same rays as `exao query`.
  const float radius = options.radius.value_or(5.0f * 0.01f * diagonal);
  const float offset = options.origin_offset.value_or(kDefaultOffsetFraction * diagonal);
  if (!(std::isfinite(radius) && radius > 0.0f)) {
    return invalid("options.radius: the default (5% of the diagonal) is not a positive length for this scene");
  }
  if (!std::isfinite(offset)) return invalid("options.origin_offset: the default (1e-4 of the diagonal) is not finite");

  auto impl = std::make_unique<Engine::Impl>();
  impl->arena = std::make_unique<tbb::task_arena>(options.threads > 0 ? options.threads : static_cast<int>(tbb::task_arena::automatic));
  impl->arena->initialize();

  std::optional<Error> failed;
  impl->arena->execute([&] {
    auto pattern = make_sample_pattern(options.samples, to_internal(options.falloff), options.pattern_seed);
    if (!pattern) {
      failed = invalid(pattern.error().message);
      return;
    }
    auto rays = make_shadow_rays(std::move(*pattern), radius, offset);
    if (!rays) {
      failed = invalid(rays.error().message);
      return;
    }
    impl->rays = std::move(*rays);
    if (options.backend == Backend::Embree) {
      auto embree = EmbreeScene::build(scene);
      if (!embree) {
        failed = detail::from_internal(StatusCode::BackendError, embree.error());
        return;
      }
      impl->embree = std::make_unique<EmbreeScene>(std::move(*embree));
      return;
    }
    const lut::MaskMode mode = options.mask_mode == MaskMode::Exact ? lut::MaskMode::Exact : lut::MaskMode::Lut;
    auto masks = lut::MaskEngine::build(impl->rays, mode, options.table_resolution);
    if (!masks) {
      failed = invalid(masks.error().message);
      return;
    }
    impl->masks = std::move(*masks);
    auto triangles = std::make_unique<lut::TriangleSet>(lut::TriangleSet::build(scene));
    if (options.backend == Backend::Brute) {
      impl->triangles = std::move(triangles);
      return;
    }
    bvh::BvhOptions bvh_options;
    bvh_options.branching = options.bvh_branching;
    auto built = bvh::Bvh::build(*triangles, bvh_options);
    if (!built) {
      failed = detail::from_internal(StatusCode::BackendError, built.error());
      return;
    }
    impl->bvh = std::make_unique<bvh::Bvh>(std::move(*built));
  });
  if (failed) return std::move(*failed);

  EngineInfo& info = impl->info;
  info.backend = options.backend;
  info.mask_mode = options.mask_mode;
  info.falloff = options.falloff;
  info.samples = options.samples;
  info.mask_words = static_cast<std::size_t>(options.samples + 63) / 64;
  info.radius = radius;
  info.origin_offset = offset;
  info.threads = impl->arena->max_concurrency();
  info.triangles = scene.triangle_count();
  info.two_sided_triangles = two_sided_count(scene);
  info.zero_area_skipped = zero_area_skipped;
  info.bounds_lo = {bounds.lo.x, bounds.lo.y, bounds.lo.z};
  info.bounds_hi = {bounds.hi.x, bounds.hi.y, bounds.hi.z};
  info.table_resolution = impl->masks ? impl->masks->table_resolution() : 0;
  info.table_bytes = impl->masks ? impl->masks->table_bytes() : 0;
  info.simd = simd_name();
  impl->embree_rays = options.embree_rays;
  return impl;
}

// --- Queries ------------------------------------------------------------------------------------

// The mask of one receiver into words[0, mask_words), on the calling thread.
void single_mask(const Engine::Impl& impl, const exao::Receiver& receiver, std::uint64_t* words) {
  const int n = impl.rays.count();
  const std::size_t count = impl.info.mask_words;
  if (impl.embree) {
    // One receiver: single rays (packets across receivers would have one live lane).
    EmbreeOptions embree_options;
    embree_options.rays = exao::EmbreeRays::Single;
    const MaskSet set = impl.embree->occlusion(impl.rays, std::span<const exao::Receiver>(&receiver, 1), embree_options);
    std::copy_n(set.row(0).begin(), count, words);
    return;
  }
  const Frame frame = impl.rays.frame(receiver);
  with_mask_bits(n, [&](auto bits) {
    constexpr int Bits = decltype(bits)::value;
    const lut::FlushDenormals flush;  // the same float mode on every thread (lut/float_mode.h)
    Mask<Bits> mask;
    if (impl.bvh) {
      mask = bvh::traverse<Bits, false>(*impl.bvh, *impl.masks, frame, nullptr);
    } else {
      const Mask<Bits> all = impl.masks->all_rays<Bits>();
      for (std::uint32_t t = 0; t < impl.triangles->size(); ++t) {
        mask |= impl.masks->triangle_mask<Bits>(*impl.triangles, t, frame);
        if (mask == all) break;  // nothing left to block
      }
    }
    std::copy_n(mask.words.begin(), count, words);
  });
}

void fill_rays(const Engine::Impl& impl, const exao::Receiver& receiver, Vec3* origin, std::span<ShadowRay> rays) {
  const Frame frame = impl.rays.frame(receiver);
  if (origin) *origin = {frame.origin.x, frame.origin.y, frame.origin.z};
  const SamplePattern& pattern = impl.rays.pattern;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const glm::vec3 d = frame.to_world_direction(pattern.directions[i]);
    rays[i] = {{d.x, d.y, d.z}, pattern.lengths[i] * impl.rays.radius};
  }
}

[[nodiscard]] int popcount_words(const std::uint64_t* words, std::size_t count) {
  int n = 0;
  for (std::size_t w = 0; w < count; ++w) n += std::popcount(words[w]);
  return n;
}

// AO from a blocked count, the same float as MaskSet::ao (what `exao query` writes).
[[nodiscard]] float ao_of(int blocked, int samples) {
  return 1.0f - static_cast<float>(blocked) / static_cast<float>(samples);
}

// The bvh backend's batch: receivers in Morton order on the engine's arena, every chunk inside a
// FlushDenormals like single queries, so a receiver's bits never depend on the thread.
template <int Bits, bool Stats>
void bvh_batch(const Engine::Impl& impl, std::span<const exao::Receiver> receivers, std::uint64_t* words, float* ao,
               const BatchOptions& batch) {
  const std::vector<std::uint32_t> order = morton_order(receivers);
  const std::size_t count = impl.info.mask_words;
  const int n = impl.rays.count();
  ProgressCounter counter(batch.progress, receivers.size());
  tbb::combinable<bvh::TraversalStats> local;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, order.size(), 64), [&](const tbb::blocked_range<std::size_t>& range) {
    const lut::FlushDenormals flush;
    bvh::TraversalStats& mine = local.local();
    for (std::size_t i = range.begin(); i < range.end(); ++i) {
      const std::uint32_t r = order[i];
      const Frame frame = impl.rays.frame(receivers[r]);
      const Mask<Bits> mask = bvh::traverse<Bits, Stats>(*impl.bvh, *impl.masks, frame, &mine);
      if (words) std::copy_n(mask.words.begin(), count, words + r * count);
      if (ao) ao[r] = ao_of(mask.popcount(), n);
    }
    counter.add(range.size());
  });
  if constexpr (Stats) {
    local.combine_each([&](const bvh::TraversalStats& s) {
      batch.stats->receivers += s.receivers;
      batch.stats->nodes_visited += s.nodes_visited;
      batch.stats->triangles_tested += s.triangles_tested;
      batch.stats->triangles_blocking += s.triangles_blocking;
    });
  }
}

// A batch into `words` (count * mask_words) and/or `ao` (count), either may be null.
[[nodiscard]] Status run_batch(const Engine::Impl* impl, std::span<const Receiver> receivers, std::uint64_t* words,
                               float* ao, const BatchOptions& batch) {
  if (!impl) return invalid("engine: empty (moved from)");
  for (std::size_t i = 0; i < receivers.size(); ++i) {
    if (const char* problem = receiver_problem(receivers[i])) {
      return invalid("receivers[" + std::to_string(i) + "]: " + problem);
    }
  }
  if (receivers.empty()) return {};
  std::vector<exao::Receiver> internal(receivers.size());
  for (std::size_t i = 0; i < receivers.size(); ++i) internal[i] = to_internal(receivers[i]);

  const std::size_t count = impl->info.mask_words;
  const int n = impl->rays.count();
  impl->arena->execute([&] {
    if (impl->bvh) {
      with_mask_bits(n, [&](auto bits) {
        constexpr int Bits = decltype(bits)::value;
        if (batch.stats) {
          bvh_batch<Bits, true>(*impl, internal, words, ao, batch);
        } else {
          bvh_batch<Bits, false>(*impl, internal, words, ao, batch);
        }
      });
      return;
    }
    MaskSet set;
    if (impl->embree) {
      EmbreeOptions embree_options;
      embree_options.rays = to_internal_rays(batch.embree_rays.value_or(impl->embree_rays));
      set = impl->embree->occlusion(impl->rays, internal, embree_options, batch.progress);
    } else {
      set = lut::brute_occlusion(*impl->masks, *impl->triangles, internal, batch.progress);
    }
    for (std::size_t i = 0; i < internal.size(); ++i) {
      if (words) std::copy_n(set.row(i).begin(), count, words + i * count);
      if (ao) ao[i] = set.ao(i);
    }
  });
  return {};
}

}  // namespace

// --- Public functions ---------------------------------------------------------------------------

Engine::Engine(std::unique_ptr<Impl> impl) noexcept : impl_(std::move(impl)) {}
Engine::Engine(Engine&&) noexcept = default;
Engine& Engine::operator=(Engine&&) noexcept = default;
Engine::~Engine() = default;

Result<Engine> Engine::build(std::span<const Mesh> meshes, const Options& options) noexcept {
  return guard<Result<Engine>>([&]() -> Result<Engine> {
    if (std::optional<Error> bad = check_options(options)) return std::move(*bad);
    if (meshes.empty()) return invalid("meshes: none given");
    if (!meshes.data()) return invalid("meshes: null");
    Scene scene;
    scene.name = "meshes";
    for (std::size_t k = 0; k < meshes.size(); ++k) {
      if (std::optional<Error> bad = add_mesh(scene, meshes[k], k)) return std::move(*bad);
    }
    Result<std::unique_ptr<Impl>> impl = build_impl(scene, options, scene.report.zero_area_skipped);
    if (!impl) return impl.error();
    return Engine(std::move(*impl));
  });
}

Result<Engine> Engine::open(std::string_view name_or_path, const Options& options) noexcept {
  return guard<Result<Engine>>([&]() -> Result<Engine> {
    if (std::optional<Error> bad = check_options(options)) return std::move(*bad);
    if (name_or_path.empty()) return invalid("name_or_path: empty");
    exao::Result<Scene> scene = open_scene(std::string(name_or_path));
    if (!scene) return detail::from_internal(StatusCode::FileError, scene.error());
    Result<std::unique_ptr<Impl>> impl = build_impl(*scene, options, 0);
    if (!impl) return impl.error();
    return Engine(std::move(*impl));
  });
}

const EngineInfo& Engine::info() const noexcept { return impl_ ? impl_->info : kEmptyInfo; }

Result<float> Engine::ao(const Receiver& receiver) const noexcept {
  return guard<Result<float>>([&]() -> Result<float> {
    if (!impl_) return invalid("engine: empty (moved from)");
    if (const char* problem = receiver_problem(receiver)) return invalid(std::string("receiver: ") + problem);
    std::uint64_t words[RayMask::kMaxSamples / 64] = {};
    single_mask(*impl_, to_internal(receiver), words);
    return ao_of(popcount_words(words, impl_->info.mask_words), impl_->info.samples);
  });
}

Result<RayMask> Engine::mask(const Receiver& receiver, std::span<ShadowRay> rays) const noexcept {
  return guard<Result<RayMask>>([&]() -> Result<RayMask> {
    if (!impl_) return invalid("engine: empty (moved from)");
    if (const char* problem = receiver_problem(receiver)) return invalid(std::string("receiver: ") + problem);
    const auto n = static_cast<std::size_t>(impl_->info.samples);
    if (!rays.empty() && rays.size() != n) {
      return invalid("rays: must hold 0 or N = " + std::to_string(n) + " entries, holds " + std::to_string(rays.size()));
    }
    const exao::Receiver internal = to_internal(receiver);
    RayMask mask;
    mask.samples = impl_->info.samples;
    single_mask(*impl_, internal, mask.words.data());
    if (!rays.empty()) fill_rays(*impl_, internal, nullptr, rays);
    return mask;
  });
}

Status Engine::rays(const Receiver& receiver, Vec3& origin, std::span<ShadowRay> rays) const noexcept {
  return guard<Status>([&]() -> Status {
    if (!impl_) return invalid("engine: empty (moved from)");
    if (const char* problem = receiver_problem(receiver)) return invalid(std::string("receiver: ") + problem);
    const auto n = static_cast<std::size_t>(impl_->info.samples);
    if (rays.size() != n) {
      return invalid("rays: must hold N = " + std::to_string(n) + " entries, holds " + std::to_string(rays.size()));
    }
    fill_rays(*impl_, to_internal(receiver), &origin, rays);
    return {};
  });
}

Status Engine::ao(std::span<const Receiver> receivers, std::span<float> ao, const BatchOptions& batch) const noexcept {
  return guard<Status>([&]() -> Status {
    if (ao.size() != receivers.size()) {
      return invalid("ao: must hold one value per receiver (" + std::to_string(receivers.size()) + "), holds " +
                     std::to_string(ao.size()));
    }
    if (!receivers.empty() && (!receivers.data() || !ao.data())) return invalid("receivers or ao: null");
    return run_batch(impl_.get(), receivers, nullptr, ao.data(), batch);
  });
}

Status Engine::masks(std::span<const Receiver> receivers, std::span<std::uint64_t> words, const BatchOptions& batch) const noexcept {
  return guard<Status>([&]() -> Status {
    const std::size_t per = mask_words();
    if (words.size() != receivers.size() * per) {
      return invalid("words: must hold mask_words() = " + std::to_string(per) + " words per receiver (" +
                     std::to_string(receivers.size() * per) + "), holds " + std::to_string(words.size()));
    }
    if (!receivers.empty() && (!receivers.data() || !words.data())) return invalid("receivers or words: null");
    return run_batch(impl_.get(), receivers, words.data(), nullptr, batch);
  });
}

}  // namespace exao::api
