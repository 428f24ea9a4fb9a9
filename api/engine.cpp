// exao::api::Engine: the public AO engine, a thin boundary over the library's one engine
// (engine/engine.h, which every exao command uses too): it checks the caller's arrays and
// receivers, turns the public types into the library's, names options as the public Options
// does, and maps errors to status codes. The rays are those of the exao program for the same
// scene and options, so the bits are the same as `exao query`'s (tests/api_cpp_test.cpp).

#include <algorithm>
#include <array>
#include <atomic>
#include <cfloat>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "api/boundary.h"
#include "core/coordinate_limit.h"
#include "io/load_scene.h"
#include "core/mask.h"
#include "core/receiver_frame.h"
#include "core/scene.h"
#include "engine/engine.h"
#include "engine/receiver_check.h"
#include "exao/exao.hpp"

namespace exao::api {

using detail::guard;
using detail::invalid;

// How build's meshes became the scene's triangles, for refit: per placement (mesh, or
// instance) its mesh and triangle count, and per triangle given whether it was kept.
struct SceneLayout {
  bool instanced = false;
  std::vector<std::size_t> mesh;       // per placement
  std::vector<std::size_t> triangles;  // per placement: its mesh's triangle_count at build
  std::vector<bool> kept;              // per triangle given, in placement order
};

struct Engine::Impl {
  engine::Engine engine;
  EngineInfo info;
  std::shared_ptr<const SceneLayout> layout;  // null for Engine::open (a file has no arrays to refit)
};

namespace {

const EngineInfo kEmptyInfo{};


// --- Options ------------------------------------------------------------------------------------

// The library's option names (engine/options.h) as the public Options names them.
constexpr std::array<std::pair<std::string_view, std::string_view>, 12> kOptionNames{{
    {"radius", "radius"},
    {"samples", "samples"},
    {"falloff", "falloff"},
    {"pattern_seed", "pattern_seed"},
    {"origin_offset", "origin_offset"},
    {"sidedness", "sidedness"},
    {"method", "backend"},
    {"masks", "mask_mode"},
    {"threads", "threads"},
    {"table_resolution", "table_resolution"},
    {"bvh.branching", "bvh_branching"},
    {"embree.rays", "embree_rays"},
}};

// An error of the library engine: "options.<public name>: ..." when it is about an option
// (InvalidArgument), else `code` with the message as it is.
[[nodiscard]] Error from_engine(const exao::Error& error, StatusCode code) {
  if (const std::optional<std::string_view> option = engine::option_of(error.message)) {
    std::string_view name = *option;
    for (const auto& [internal, public_name] : kOptionNames) {
      if (internal == *option) name = public_name;
    }
    return invalid("options." + std::string(name) + error.message.substr(option->size()));
  }
  // The environment's EXAO_ISA is the caller's input too (core/isa.h).
  if (error.message.starts_with("EXAO_ISA:")) return invalid(error.message);
  return detail::make_error(code, error.message);
}

[[nodiscard]] engine::Options to_engine(const Options& o) {
  engine::Options out;
  if (o.radius) out.radius = engine::Length{*o.radius, false};
  out.samples = o.samples;
  out.falloff = static_cast<exao::Falloff>(static_cast<int>(o.falloff));
  out.pattern_seed = o.pattern_seed;
  out.origin_offset = o.origin_offset;
  out.offset_default = engine::OffsetDefault::PointScale;  // the API's default (exao.hpp, Options)
  out.sidedness = static_cast<exao::Sidedness>(static_cast<int>(o.sidedness));
  out.method = o.backend == Backend::Bvh      ? engine::Method::Bvh
               : o.backend == Backend::Brute  ? engine::Method::Brute
               : o.backend == Backend::Embree ? engine::Method::Embree
               : o.backend == Backend::Raster ? engine::Method::Raster
               : o.backend == Backend::Auto   ? engine::Method::Auto
                                              : static_cast<engine::Method>(-1);  // refused by check_options
  out.masks = static_cast<lut::MaskMode>(static_cast<int>(o.mask_mode));
  out.threads = o.threads;
  out.table_resolution = o.table_resolution;
  out.bvh.branching = o.bvh_branching;
  out.embree.rays = static_cast<exao::EmbreeRays>(static_cast<int>(o.embree_rays));
  return out;
}

[[nodiscard]] std::optional<Error> check_options(const Options& options) {
  // The public numbering of backends is not the engine's: checked here, so that the error gives
  // the value the caller passed.
  const int backend = static_cast<int>(options.backend);
  if (backend < 0 || backend > static_cast<int>(Backend::Auto)) {
    return invalid("options.backend: not a backend (0 bvh, 1 brute, 2 embree, 3 raster, 4 auto), got " +
                   std::to_string(backend));
  }
  const engine::Options o = to_engine(options);
  if (auto ok = engine::check_options(o); !ok) return from_engine(ok.error(), StatusCode::InvalidArgument);
  if (auto ok = engine::check_serves(o, engine::Receivers::Points); !ok) return from_engine(ok.error(), StatusCode::InvalidArgument);
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

// Mesh k's arrays and sizes, as build and refit read them.
[[nodiscard]] std::optional<Error> check_mesh(const Mesh& mesh, const std::string& name) {
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
  return std::nullopt;
}

[[nodiscard]] std::optional<Error> check_transform(const float* m, const std::string& name) {
  if (!m) return std::nullopt;
  for (int i = 0; i < 12; ++i) {
    if (!std::isfinite(m[i])) return invalid(name + ".transform: element " + std::to_string(i) + " is not finite");
  }
  return std::nullopt;
}

// Triangle t of a checked mesh in world units: its vertices through the mesh's transform, then
// the instance's (nullptr: none).
[[nodiscard]] std::optional<Error> world_triangle(const Mesh& mesh, const float* instance, std::size_t t,
                                                  const std::string& name, glm::vec3 (&v)[3]) {
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
  for (int j = 0; j < 3; ++j) {
    v[j] = place(instance, place(mesh.transform, read_vertex(mesh, index[j])));
    if (!(std::isfinite(v[j].x) && std::isfinite(v[j].y) && std::isfinite(v[j].z))) {
      return invalid(name + ": triangle " + std::to_string(t) + " has a non-finite vertex (" + std::to_string(index[j]) +
                     (mesh.transform || instance ? ", after the transform)" : ")"));
    }
  }
  return std::nullopt;
}

// One placement of a mesh in the scene: the mesh (meshes[mesh]) and its instance transform.
struct Placement {
  std::size_t mesh = 0;
  const float* transform = nullptr;
};

// The placements of build's arguments: one per mesh, or one per instance. Checks them.
[[nodiscard]] Result<std::vector<Placement>> placements_of(std::span<const Mesh> meshes,
                                                           std::optional<std::span<const Instance>> instances) {
  if (meshes.empty()) return invalid("meshes: none given");
  if (!meshes.data()) return invalid("meshes: null");
  for (std::size_t k = 0; k < meshes.size(); ++k) {
    if (std::optional<Error> bad = check_mesh(meshes[k], "meshes[" + std::to_string(k) + "]")) return std::move(*bad);
  }
  std::vector<Placement> out;
  if (!instances) {
    for (std::size_t k = 0; k < meshes.size(); ++k) out.push_back({k, nullptr});
    return out;
  }
  if (instances->empty()) return invalid("instances: none given");
  if (!instances->data()) return invalid("instances: null");
  if (instances->size() >= kNoObject) return invalid("instances: more than 2^32 - 2");
  for (std::size_t i = 0; i < instances->size(); ++i) {
    const Instance& instance = (*instances)[i];
    const std::string name = "instances[" + std::to_string(i) + "]";
    if (instance.mesh >= meshes.size()) {
      return invalid(name + ".mesh: " + std::to_string(instance.mesh) + " is not a mesh (" +
                     std::to_string(meshes.size()) + " given)");
    }
    if (std::optional<Error> bad = check_transform(instance.transform, name)) return std::move(*bad);
    out.push_back({instance.mesh, instance.transform});
  }
  return out;
}

// The name of placement k in errors: its mesh, or the instance and its mesh.
[[nodiscard]] std::string placement_name(const std::vector<Placement>& placements, std::size_t k, bool instanced) {
  const std::string mesh = "meshes[" + std::to_string(placements[k].mesh) + "]";
  return instanced ? "instances[" + std::to_string(k) + "] (" + mesh + ")" : mesh;
}

// Appends every placement's triangles to `scene`, object k for placement k; zero-area ones are
// dropped (they block no ray in any backend), counted in scene.report, and their bit of `kept`
// (one per triangle given, in placement order) left 0.
[[nodiscard]] std::optional<Error> add_placements(Scene& scene, std::span<const Mesh> meshes,
                                                  const std::vector<Placement>& placements, bool instanced,
                                                  std::vector<bool>& kept) {
  for (std::size_t k = 0; k < placements.size(); ++k) {
    const Mesh& mesh = meshes[placements[k].mesh];
    const std::size_t n = mesh.triangle_count;
    if (n == 0) continue;
    const std::string name = placement_name(placements, k, instanced);
    scene.vertices.reserve(scene.vertices.size() + 3 * n);
    scene.two_sided.reserve(scene.two_sided.size() + n);
    scene.material.reserve(scene.material.size() + n);
    scene.object.reserve(scene.object.size() + n);
    for (std::size_t t = 0; t < n; ++t) {
      glm::vec3 v[3];
      if (std::optional<Error> bad = world_triangle(mesh, placements[k].transform, t, name, v)) return bad;
      const bool two = mesh.two_sided ? mesh.two_sided[t] != 0 : true;
      const bool added = scene.add_triangle(v[0], v[1], v[2], two, -1);
      if (added) scene.object.push_back(static_cast<std::uint32_t>(k));
      kept.push_back(added);
    }
  }
  return std::nullopt;
}

// --- Receivers ----------------------------------------------------------------------------------

[[nodiscard]] const char* receiver_problem(const Receiver& r) {
  return engine::receiver_problem(glm::vec3(r.position.x, r.position.y, r.position.z),
                                  glm::vec3(r.normal.x, r.normal.y, r.normal.z));
}

[[nodiscard]] exao::Receiver to_internal(const Receiver& r) {
  return {glm::vec3(r.position.x, r.position.y, r.position.z), glm::vec3(r.normal.x, r.normal.y, r.normal.z), r.key,
          r.excluded_object};
}

// --- Build --------------------------------------------------------------------------------------

// Why no triangle is left, from what the scene's report says was dropped.
[[nodiscard]] std::string nothing_left(const Scene& scene) {
  const LoadReport& report = scene.report;
  std::string why;
  if (report.non_finite_skipped > 0) {
    why += std::to_string(report.non_finite_skipped) + " with a vertex beyond +-1e17 (Embree's limit) or not finite";
  }
  if (report.zero_area_skipped > 0) {
    why += (why.empty() ? "" : ", ") + std::to_string(report.zero_area_skipped) + " of zero area";
  }
  if (why.empty()) return "the scene has no triangle";
  return "no triangle left of the " + std::to_string(report.non_finite_skipped + report.zero_area_skipped +
                                                     scene.triangle_count()) +
         " given: " + why + " (they block no ray)";
}

// The engine takes the scene (no copy; its arrays freed as the backends are built).
[[nodiscard]] Result<std::unique_ptr<Engine::Impl>> build_impl(Scene&& scene, const Options& options,
                                                                StatusCode empty_code) {
  if (scene.triangle_count() == 0) return detail::make_error(empty_code, nothing_left(scene));
  const LoadReport report = scene.report;
  Result<engine::Engine> built = [&]() -> Result<engine::Engine> {
    exao::Result<engine::Engine> e = engine::Engine::build(std::move(scene), to_engine(options), engine::Receivers::Points);
    if (!e) return from_engine(e.error(), StatusCode::BackendError);
    return std::move(*e);
  }();
  if (!built) return built.error();
  auto impl = std::make_unique<Engine::Impl>(Engine::Impl{std::move(*built), {}, nullptr});
  const engine::Engine& e = impl->engine;
  const Bounds& bounds = e.geometry().bounds();
  EngineInfo& info = impl->info;
  info.backend = options.backend;
  info.mask_mode = options.mask_mode;
  info.falloff = options.falloff;
  info.samples = e.samples();
  info.mask_words = e.mask_words();
  info.radius = e.radius();
  info.origin_offset = e.origin_offset();
  info.origin_offset_per_magnitude = e.rays().offset_per_magnitude;
  info.threads = e.threads();
  info.triangles = e.geometry().triangle_count();
  info.two_sided_triangles = e.geometry().two_sided_count();
  info.zero_area_skipped = report.zero_area_skipped;
  info.beyond_limit_skipped = report.non_finite_skipped;
  info.bounds_lo = {bounds.lo.x, bounds.lo.y, bounds.lo.z};
  info.bounds_hi = {bounds.hi.x, bounds.hi.y, bounds.hi.z};
  info.table_resolution = e.mask_engine() ? e.mask_engine()->table_resolution() : 0;
  info.table_bytes = e.mask_engine() ? e.mask_engine()->table_bytes() : 0;
  info.simd = e.mask_engine() ? isa_name(e.mask_engine()->isa()) : "none";
  return impl;
}

// --- Queries ------------------------------------------------------------------------------------

void fill_rays(const Engine::Impl& impl, const exao::Receiver& receiver, Vec3* origin, std::span<ShadowRay> rays) {
  const Frame frame = impl.engine.rays().frame(receiver);
  if (origin) *origin = {frame.origin.x, frame.origin.y, frame.origin.z};
  const SamplePattern& pattern = impl.engine.rays().pattern;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const glm::vec3 d = frame.to_world_direction(pattern.directions[i]);
    rays[i] = {{d.x, d.y, d.z}, pattern.lengths[i] * impl.engine.rays().radius};
  }
}

[[nodiscard]] int popcount_words(std::span<const std::uint64_t> words) {
  int n = 0;
  for (const std::uint64_t w : words) n += std::popcount(w);
  return n;
}

// Thrown through the engine's workers by the progress wrapper to stop a batch (TBB carries it
// to the caller's thread); the reason is in the BatchStop it points to.
struct StopBatch {};

// Why a batch stopped early, shared by the workers: the first reason wins.
struct BatchStop {
  std::atomic<int> reason{0};  // 0 running, 1 cancelled, 2 the callback threw
  std::mutex mutex;
  std::string thrown;          // the callback's what(), under mutex
  std::size_t done = 0, total = 0;

  [[noreturn]] void stop(int why, std::string message, std::size_t at, std::size_t of) {
    int running = 0;
    if (reason.compare_exchange_strong(running, why)) {
      const std::lock_guard lock(mutex);
      thrown = std::move(message);
      done = at;
      total = of;
    }
    throw StopBatch{};
  }
};

// The receivers a batch computes: the good ones (indices into the batch); each bad one set
// aside (AO NaN, mask zero, its status), the first named for the batch's error.
struct SetAside {
  std::vector<std::uint32_t> good;
  std::size_t bad = 0;
  std::string first_bad;

  [[nodiscard]] Status status(std::size_t receivers) const {
    if (bad == 0) return {};
    return invalid(first_bad + " (" + std::to_string(bad) + " of " + std::to_string(receivers) +
                   " receivers are bad: their AO is NaN; the others were computed)");
  }
};

SetAside set_aside_bad(std::span<const Receiver> receivers, std::span<std::uint64_t> words, std::span<float> ao,
                       const BatchOptions& batch, std::size_t per) {
  SetAside out;
  out.good.reserve(receivers.size());
  for (std::size_t i = 0; i < receivers.size(); ++i) {
    const char* problem = receiver_problem(receivers[i]);
    if (!batch.statuses.empty()) batch.statuses[i] = problem ? StatusCode::InvalidArgument : StatusCode::Ok;
    if (!problem) {
      out.good.push_back(static_cast<std::uint32_t>(i));
      continue;
    }
    if (out.bad++ == 0) out.first_bad = "receivers[" + std::to_string(i) + "]: " + problem;
    if (!ao.empty()) ao[i] = std::numeric_limits<float>::quiet_NaN();
    if (!words.empty()) std::fill_n(words.begin() + static_cast<std::ptrdiff_t>(i * per), per, std::uint64_t{0});
  }
  return out;
}

// The engine's progress callback for batch.progress: the caller counts its own receivers (the
// `bad` ones done from the start); a false answer or a throw stops the batch through `stop`.
ProgressCallback batch_progress(const BatchOptions& batch, BatchStop& stop, std::size_t bad) {
  if (!batch.progress) return {};
  return [&batch, &stop, bad](std::size_t done, std::size_t total) {
    if (stop.reason.load(std::memory_order_relaxed) != 0) throw StopBatch{};
    const std::size_t at = done + bad, of = total + bad;
    bool go = true;
    try {
      go = batch.progress(at, of);
    } catch (const std::exception& e) {
      stop.stop(2, e.what(), at, of);
    } catch (...) {
      stop.stop(2, "an exception that is not a std::exception", at, of);
    }
    if (!go) stop.stop(1, {}, at, of);
  };
}

// The engine's counters into the caller's.
void add_stats(const engine::Stats& stats, WorkStats& out) {
  out.receivers += stats.traversal.receivers;
  out.nodes_visited += stats.traversal.nodes_visited;
  out.triangles_tested += stats.traversal.triangles_tested;
  out.triangles_blocking += stats.traversal.triangles_blocking;
}

// A batch into `words` (count * mask_words) and/or `ao` (count), either may be empty.
[[nodiscard]] Status run_batch(const Engine::Impl* impl, std::span<const Receiver> receivers, std::span<std::uint64_t> words,
                               std::span<float> ao, const BatchOptions& batch) {
  if (!impl) return invalid("engine: empty (moved from)");
  if (!batch.statuses.empty() && batch.statuses.size() != receivers.size()) {
    return invalid("batch.statuses: must hold 0 entries or one per receiver (" + std::to_string(receivers.size()) +
                   "), holds " + std::to_string(batch.statuses.size()));
  }
  const std::size_t per = impl->info.mask_words;
  const SetAside sorted = set_aside_bad(receivers, words, ao, batch, per);
  const std::vector<std::uint32_t>& good = sorted.good;
  if (good.empty()) return sorted.status(receivers.size());
  // The good receivers, compacted; results go to scratch arrays when some were set aside.
  const bool compact = good.size() != receivers.size();
  std::vector<exao::Receiver> internal(good.size());
  for (std::size_t k = 0; k < good.size(); ++k) internal[k] = to_internal(receivers[good[k]]);
  std::vector<float> ao_scratch(compact && !ao.empty() ? good.size() : 0);
  std::vector<std::uint64_t> words_scratch(compact && !words.empty() ? good.size() * per : 0);
  engine::Stats stats;
  engine::RunOptions run;
  BatchStop stop;
  run.progress = batch_progress(batch, stop, sorted.bad);
  if (batch.stats) run.stats = &stats;
  if (batch.embree_rays) run.embree_rays = static_cast<exao::EmbreeRays>(static_cast<int>(*batch.embree_rays));
  engine::Outputs outputs;
  outputs.ao = compact && !ao.empty() ? std::span<float>(ao_scratch) : ao;
  outputs.masks = compact && !words.empty() ? std::span<std::uint64_t>(words_scratch) : words;
  try {
    if (auto ok = impl->engine.run(internal, outputs, run); !ok) return from_engine(ok.error(), StatusCode::InternalError);
  } catch (const StopBatch&) {
    const std::lock_guard lock(stop.mutex);
    const std::string where = " at " + std::to_string(stop.done) + " of " + std::to_string(stop.total) + " receivers";
    if (stop.reason.load() == 1) return detail::make_error(StatusCode::Cancelled, "batch.progress: returned false" + where);
    return detail::make_error(StatusCode::CallbackError, "batch.progress: threw" + where + ": " + stop.thrown);
  }
  if (compact) {
    for (std::size_t k = 0; k < good.size(); ++k) {
      const std::size_t i = good[k];
      if (!ao.empty()) ao[i] = ao_scratch[k];
      if (!words.empty()) std::copy_n(words_scratch.begin() + static_cast<std::ptrdiff_t>(k * per), per, words.begin() + static_cast<std::ptrdiff_t>(i * per));
    }
  }
  if (batch.stats) add_stats(stats, *batch.stats);
  return sorted.status(receivers.size());
}

}  // namespace

// --- Public functions ---------------------------------------------------------------------------

Engine::Engine(std::unique_ptr<Impl> impl) noexcept : impl_(std::move(impl)) {}
Engine::Engine(Engine&&) noexcept = default;
Engine& Engine::operator=(Engine&&) noexcept = default;
Engine::~Engine() = default;

namespace {

[[nodiscard]] Result<Engine::Impl*> build_placed(std::span<const Mesh> meshes,
                                                 std::optional<std::span<const Instance>> instances,
                                                 const Options& options) {
  if (std::optional<Error> bad = check_options(options)) return std::move(*bad);
  Result<std::vector<Placement>> placements = placements_of(meshes, instances);
  if (!placements) return placements.error();
  auto layout = std::make_shared<SceneLayout>();
  layout->instanced = instances.has_value();
  Scene scene;
  scene.name = "meshes";
  if (std::optional<Error> bad = add_placements(scene, meshes, *placements, layout->instanced, layout->kept)) {
    return std::move(*bad);
  }
  for (const Placement& p : *placements) {
    layout->mesh.push_back(p.mesh);
    layout->triangles.push_back(meshes[p.mesh].triangle_count);
  }
  Result<std::unique_ptr<Engine::Impl>> impl = build_impl(std::move(scene), options, StatusCode::InvalidArgument);
  if (!impl) return impl.error();
  (*impl)->layout = std::move(layout);
  return impl->release();
}

}  // namespace

Result<Engine> Engine::build(std::span<const Mesh> meshes, const Options& options) noexcept {
  return guard<Result<Engine>>([&]() -> Result<Engine> {
    Result<Impl*> impl = build_placed(meshes, std::nullopt, options);
    if (!impl) return impl.error();
    return Engine(std::unique_ptr<Impl>(*impl));
  });
}

Result<Engine> Engine::build(std::span<const Mesh> meshes, std::span<const Instance> instances,
                             const Options& options) noexcept {
  return guard<Result<Engine>>([&]() -> Result<Engine> {
    Result<Impl*> impl = build_placed(meshes, instances, options);
    if (!impl) return impl.error();
    return Engine(std::unique_ptr<Impl>(*impl));
  });
}

Status Engine::refit(std::span<const Mesh> meshes, std::span<const Instance> instances) noexcept {
  return guard<Status>([&]() -> Status {
    if (!impl_) return invalid("engine: empty (moved from)");
    if (!impl_->layout) return invalid("engine: opened from a file, which has no arrays to refit");
    const SceneLayout& layout = *impl_->layout;
    if (layout.instanced == instances.empty()) {
      return invalid(layout.instanced ? "instances: the engine was built with instances, none given"
                                      : "instances: the engine was built without instances");
    }
    Result<std::vector<Placement>> placements =
        placements_of(meshes, layout.instanced ? std::optional(instances) : std::nullopt);
    if (!placements) return placements.error();
    if (placements->size() != layout.mesh.size()) {
      return invalid(std::string(layout.instanced ? "instances" : "meshes") + ": " +
                     std::to_string(placements->size()) + " given, build had " + std::to_string(layout.mesh.size()));
    }
    std::vector<glm::vec3> vertices;
    vertices.reserve(3 * impl_->info.triangles);
    std::size_t given = 0;
    for (std::size_t k = 0; k < placements->size(); ++k) {
      const Placement& p = (*placements)[k];
      const std::string name = placement_name(*placements, k, layout.instanced);
      if (p.mesh != layout.mesh[k]) {
        return invalid(name + ": build placed meshes[" + std::to_string(layout.mesh[k]) + "] here");
      }
      const Mesh& mesh = meshes[p.mesh];
      if (mesh.triangle_count != layout.triangles[k]) {
        return invalid(name + ".triangle_count: " + std::to_string(mesh.triangle_count) + ", build had " +
                       std::to_string(layout.triangles[k]));
      }
      for (std::size_t t = 0; t < mesh.triangle_count; ++t, ++given) {
        if (!layout.kept[given]) continue;
        glm::vec3 v[3];
        if (std::optional<Error> bad = world_triangle(mesh, p.transform, t, name, v)) return std::move(*bad);
        for (const glm::vec3& corner : v) {
          if (!within_coordinate_limit(corner)) {
            return invalid(name + ": triangle " + std::to_string(t) + " has a vertex beyond +-1e17 (Embree's limit)");
          }
          vertices.push_back(corner);
        }
      }
    }
    if (auto ok = impl_->engine.refit(vertices); !ok) return from_engine(ok.error(), StatusCode::BackendError);
    const Bounds& bounds = impl_->engine.geometry().bounds();
    impl_->info.bounds_lo = {bounds.lo.x, bounds.lo.y, bounds.lo.z};
    impl_->info.bounds_hi = {bounds.hi.x, bounds.hi.y, bounds.hi.z};
    return {};
  });
}

Result<Engine> Engine::open(std::string_view name_or_path, const Options& options) noexcept {
  return guard<Result<Engine>>([&]() -> Result<Engine> {
    if (std::optional<Error> bad = check_options(options)) return std::move(*bad);
    if (name_or_path.empty()) return invalid("name_or_path: empty");
    exao::Result<Scene> scene = open_scene(std::string(name_or_path));
    if (!scene) return detail::from_internal(StatusCode::FileError, scene.error());
    Result<std::unique_ptr<Impl>> impl = build_impl(std::move(*scene), options, StatusCode::FileError);
    if (!impl) return impl.error();
    return Engine(std::move(*impl));
  });
}

Result<Engine> Engine::with_settings(const QuerySettings& settings) const noexcept {
  return guard<Result<Engine>>([&]() -> Result<Engine> {
    if (!impl_) return invalid("engine: empty (moved from)");
    engine::Options options = impl_->engine.options();
    if (settings.radius) options.radius = engine::Length{*settings.radius, false};
    if (settings.origin_offset) options.origin_offset = settings.origin_offset;
    if (settings.samples) {
      options.samples = *settings.samples;
      options.given_pattern.reset();  // a new N is the generated pattern's, unless directions follow
    }
    if (!settings.directions.empty() || !settings.lengths.empty()) {
      if (!settings.directions.data() || (!settings.lengths.empty() && !settings.lengths.data())) {
        return invalid("settings.directions or settings.lengths: null");
      }
      std::vector<glm::vec3> directions(settings.directions.size());
      for (std::size_t i = 0; i < directions.size(); ++i) {
        directions[i] = {settings.directions[i].x, settings.directions[i].y, settings.directions[i].z};
      }
      exao::Result<SamplePattern> given = make_given_pattern(directions, settings.lengths);
      if (!given) return invalid("settings." + given.error().message);
      if (settings.samples && *settings.samples != given->count) {
        return invalid("settings.samples: " + std::to_string(*settings.samples) + " differs from the " +
                       std::to_string(given->count) + " directions given");
      }
      options.samples = given->count;
      options.given_pattern = std::make_shared<const SamplePattern>(std::move(*given));
    }
    exao::Result<engine::Engine> e =
        engine::Engine::build(impl_->engine.shared_geometry(), options, engine::Receivers::Points);
    if (!e) {
      Error error = from_engine(e.error(), StatusCode::InternalError);
      // The library names its options; here they are the settings'.
      if (error.message.starts_with("options.")) error.message.replace(0, 7, "settings");
      return error;
    }
    auto impl = std::make_unique<Impl>(Impl{std::move(*e), impl_->info, impl_->layout});
    EngineInfo& info = impl->info;
    info.samples = impl->engine.samples();
    info.mask_words = impl->engine.mask_words();
    info.radius = impl->engine.radius();
    info.origin_offset = impl->engine.origin_offset();
    info.origin_offset_per_magnitude = impl->engine.rays().offset_per_magnitude;
    info.table_resolution = impl->engine.mask_engine() ? impl->engine.mask_engine()->table_resolution() : 0;
    info.table_bytes = impl->engine.mask_engine() ? impl->engine.mask_engine()->table_bytes() : 0;
    return Engine(std::move(impl));
  });
}

const EngineInfo& Engine::info() const noexcept { return impl_ ? impl_->info : kEmptyInfo; }

Result<float> Engine::ao(const Receiver& receiver) const noexcept {
  return guard<Result<float>>([&]() -> Result<float> {
    if (!impl_) return invalid("engine: empty (moved from)");
    if (const char* problem = receiver_problem(receiver)) return invalid(std::string("receiver: ") + problem);
    std::array<std::uint64_t, RayMask::kMaxSamples / 64> words{};
    const std::span<std::uint64_t> mask(words.data(), impl_->info.mask_words);
    impl_->engine.mask_one(to_internal(receiver), mask);
    return ao_from_blocked(popcount_words(mask), impl_->info.samples);
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
    impl_->engine.mask_one(internal, std::span<std::uint64_t>(mask.words.data(), impl_->info.mask_words));
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
    return run_batch(impl_.get(), receivers, {}, ao, batch);
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
    return run_batch(impl_.get(), receivers, words, {}, batch);
  });
}

}  // namespace exao::api
