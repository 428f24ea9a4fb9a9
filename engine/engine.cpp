#include "engine/engine.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <mutex>
#include <ranges>
#include <string>

#include <tbb/task_arena.h>

#include "bvh/hybrid.h"
#include "bvh/occlusion.h"
#include "core/check.h"
#include "engine/morton.h"
#include "lut/brute.h"
#include "lut/float_mode.h"
#include "raster/gbuffer.h"
#include "raster/occlusion.h"

namespace exao::engine {

struct Engine::Impl {
  Options options;
  Receivers served = Receivers::Points;
  std::shared_ptr<const Geometry> geometry;
  ShadowRays rays;
  std::optional<lut::MaskEngine> masks;  // every method but embree
  std::unique_ptr<tbb::task_arena> arena;
  // Auto's cost model, one per thread, learnt across calls (bvh/hybrid.h).
  std::unique_ptr<bvh::HybridControllers> hybrid = std::make_unique<bvh::HybridControllers>();

  // Radii far beyond the scene (issue 22). The masks work in units of r, so at r = 1e16 a
  // room's coordinates are ~1e-15 there, their products ~1e-30 and their squares underflow:
  // triangles were dropped (the edge normals' 1e-30 degeneracy test, then FTZ) and AO came out
  // 1 where Embree says 0. But no segment from p' reaches geometry beyond `reach`, the distance
  // from p' to the farthest corner of the occluders' box, so a segment of length L >= reach hits
  // exactly what one of any other length >= reach hits. Hence for receivers within `reach` of
  // everything, with r' >= reach, the rays (w_i, l_i r) and (w_i, l'_i r') with
  //     l'_i = min(1, l_i r / r')
  // hit the same triangles: a ray longer than r' becomes one of length r' >= reach, a shorter
  // one keeps its world length l_i r. Whatever the falloff, the masks are computed at r' instead
  // of r whenever r' < r, and the scene stays about unit size in the kernels' units, as at any
  // radius near the scene's size. r' is a power of two at or above reach (reach() rounds up by
  // 1e-4, far above the float rounding of l'_i r'), and at least the one above twice the
  // occluders' diagonal: so every receiver within a diagonal of the scene gets the same r', and
  // a batch, a single query and the raster pixels of the same receivers give the same bits (a
  // batch with receivers farther out uses the r' of its farthest). Each engine is built once,
  // on first use (the rays' pattern with the new lengths, the same mode, table resolution and
  // instruction set).
  // The occluders' box is read from the geometry at every query, so a refit that grows it
  // (Geometry::refit) moves reach and r' with it; the engines at r' depend on the rays only.
  [[nodiscard]] int base_exponent() const {  // 2^base_exponent >= twice the occluders' diagonal
    const Bounds& occluders = geometry->occluder_bounds();
    int exponent = 0;
    (void)std::frexp(2.0 * glm::length(glm::dvec3(occluders.hi) - glm::dvec3(occluders.lo)) * (1.0 + 1e-4), &exponent);
    return exponent;
  }
  struct ClampedMasks {
    std::once_flag once;
    std::optional<lut::MaskEngine> engine;
  };
  static constexpr int kMinExponent = -160;  // below any float: 2^-149 is the smallest
  mutable std::array<ClampedMasks, 320> clamped;  // by exponent - kMinExponent

  // The distance from p' (within its offset of the receiver's position) to the farthest
  // corner of the occluders' box, rounded up.
  [[nodiscard]] double reach(const Receiver& receiver) const {
    const glm::dvec3 p(receiver.position);
    const Bounds& occluders = geometry->occluder_bounds();
    const glm::dvec3 far = glm::max(glm::abs(p - glm::dvec3(occluders.lo)), glm::abs(p - glm::dvec3(occluders.hi)));
    return (glm::length(far) + static_cast<double>(rays.offset_at(receiver.position))) * (1.0 + 1e-4);
  }

  // The mask engine for receivers at most `reach` from every occluder: the engine at r, or the
  // one at r' above when r' < r.
  [[nodiscard]] const lut::MaskEngine& masks_for(double reach) const {
    int exponent = 0;
    (void)std::frexp(reach, &exponent);  // reach < 2^exponent
    exponent = std::max(exponent, base_exponent());
    if (!(reach > 0.0) || exponent >= kMinExponent + static_cast<int>(clamped.size()) ||
        std::ldexp(1.0, exponent) >= static_cast<double>(rays.radius)) {
      return *masks;
    }
    exponent = std::max(exponent, kMinExponent);
    ClampedMasks& slot = clamped[static_cast<std::size_t>(exponent - kMinExponent)];
    std::call_once(slot.once, [&] {
      const double shorter_radius = std::ldexp(1.0, exponent);
      const double scale = static_cast<double>(rays.radius) / shorter_radius;  // > 1
      ShadowRays shorter = rays;
      shorter.radius = static_cast<float>(shorter_radius);
      SamplePattern& pattern = shorter.pattern;
      for (std::size_t i = 0; i < pattern.lengths.size(); ++i) {
        pattern.lengths[i] = static_cast<float>(std::min(1.0, static_cast<double>(pattern.lengths[i]) * scale));
        pattern.points[i] = pattern.directions[i] * pattern.lengths[i];
      }
      // Cannot fail: the same N, mode, table resolution and level as *masks, a valid radius.
      Result<lut::MaskEngine> engine =
          lut::MaskEngine::build(shorter, masks->mode(), masks->table_resolution(), masks->isa());
      EXAO_CHECK(engine.has_value());
      slot.engine = std::move(*engine);
    });
    return *slot.engine;
  }
  [[nodiscard]] const lut::MaskEngine& masks_for(std::span<const Receiver> receivers) const {
    double farthest = 0.0;
    for (const Receiver& receiver : receivers) farthest = std::max(farthest, reach(receiver));
    return masks_for(farthest);
  }

  // The masks of consecutive receivers by the method's backend, in their order.
  [[nodiscard]] MaskSet backend_masks(std::span<const Receiver> receivers, const ProgressCallback& progress,
                                      const RunOptions& run) const {
    switch (options.method) {
      case Method::Embree: {
        EmbreeOptions embree = options.embree;
        if (run.embree_rays) embree.rays = *run.embree_rays;
        return geometry->embree()->occlusion(rays, receivers, embree, progress);
      }
      case Method::Brute:
        return lut::brute_occlusion(masks_for(receivers), *geometry->triangles(), receivers, progress);
      case Method::Bvh:
        return bvh::occlusion(*geometry->bvh(), masks_for(receivers), receivers, progress,
                              run.stats ? &run.stats->traversal : nullptr);
      case Method::Auto:
        // Embree casts the rays of the same engine (at r' when r is beyond the scene's reach):
        // they hit what the caller's rays hit.
        return bvh::hybrid_occlusion(*geometry->bvh(), masks_for(receivers), *geometry->embree(), receivers,
                                     options.hybrid, *hybrid, progress, run.stats ? &run.stats->traversal : nullptr);
      case Method::Raster: break;  // no receivers of its own choosing: refused by check_serves
    }
    EXAO_CHECK(options.method != Method::Raster);
    return {};
  }
};

namespace {

// Why an output cannot take a batch of `count` receivers, or an empty string.
std::string output_problem(const Outputs& out, std::size_t count, std::size_t words) {
  if (!out.ao.empty() && out.ao.size() != count) {
    return "outputs.ao: holds " + std::to_string(out.ao.size()) + " values for " + std::to_string(count) + " receivers";
  }
  if (!out.blocked.empty() && out.blocked.size() != count) {
    return "outputs.blocked: holds " + std::to_string(out.blocked.size()) + " values for " + std::to_string(count) +
           " receivers";
  }
  if (!out.masks.empty() && out.masks.size() != count * words) {
    return "outputs.masks: holds " + std::to_string(out.masks.size()) + " words for " + std::to_string(count) +
           " receivers of " + std::to_string(words);
  }
  return {};
}

}  // namespace

std::pair<std::size_t, std::size_t> shard_chunks(std::size_t receivers, Shard shard) {
  EXAO_CHECK(shard.count >= 1 && shard.index < shard.count);
  const std::size_t chunks = (receivers + kChunk - 1) / kChunk;
  // Products fit: chunks < 2^48 for any batch that fits in memory, count <= 2^16 in the CLI.
  return {chunks * shard.index / shard.count, chunks * (shard.index + 1) / shard.count};
}

std::vector<std::uint32_t> shard_receivers(std::span<const Receiver> receivers, Shard shard) {
  const auto [first, last] = shard_chunks(receivers.size(), shard);
  if (first == last) return {};
  const std::vector<std::uint32_t> order = morton_order(receivers);
  const std::size_t begin = first * kChunk;
  const std::size_t end = std::min(last * kChunk, receivers.size());
  return {order.begin() + static_cast<std::ptrdiff_t>(begin), order.begin() + static_cast<std::ptrdiff_t>(end)};
}

Engine::Engine(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Engine::Engine(Engine&&) noexcept = default;
Engine& Engine::operator=(Engine&&) noexcept = default;
Engine::~Engine() = default;

namespace {

// The geometry options an engine of `options` over `receivers` needs; fails on options that
// cannot serve them, before any work on the scene.
Result<GeometryOptions> geometry_options_for(const Scene& scene, const Options& options, Receivers receivers,
                                             const ProgressCallback& build_progress) {
  if (auto ok = check_options(options); !ok) return std::unexpected(ok.error());
  if (auto ok = check_serves(options, receivers); !ok) return std::unexpected(ok.error());
  GeometryOptions geometry_options;
  geometry_options.sidedness = options.sidedness;
  geometry_options.cutouts = options.cutouts;
  if (auto ok = check_serves_cutouts(options, cuts_out(scene.cutouts.get(), options.cutouts)); !ok) {
    return std::unexpected(ok.error());
  }
  geometry_options.bvh = options.bvh;
  geometry_options.embree = receivers == Receivers::Pixels && options.method != Method::Raster;
  geometry_options.threads = options.threads;
  geometry_options.progress = build_progress;
  return geometry_options;
}

}  // namespace

Result<Engine> Engine::build(const Scene& scene, const Options& options, Receivers receivers,
                             const ProgressCallback& build_progress) {
  Result<GeometryOptions> geometry_options = geometry_options_for(scene, options, receivers, build_progress);
  if (!geometry_options) return std::unexpected(geometry_options.error());
  const Method methods[] = {options.method};
  Result<std::shared_ptr<const Geometry>> geometry = Geometry::build(scene, methods, *geometry_options);
  if (!geometry) return std::unexpected(geometry.error());
  return build(std::move(*geometry), options, receivers);
}

Result<Engine> Engine::build(Scene&& scene, const Options& options, Receivers receivers,
                             const ProgressCallback& build_progress) {
  Result<GeometryOptions> geometry_options = geometry_options_for(scene, options, receivers, build_progress);
  if (!geometry_options) return std::unexpected(geometry_options.error());
  const Method methods[] = {options.method};
  Result<std::shared_ptr<const Geometry>> geometry = Geometry::build(std::move(scene), methods, *geometry_options);
  if (!geometry) return std::unexpected(geometry.error());
  return build(std::move(*geometry), options, receivers);
}

Result<Engine> Engine::build(std::shared_ptr<const Geometry> geometry, const Options& options, Receivers receivers) {
  if (auto ok = check_options(options); !ok) return std::unexpected(ok.error());
  if (auto ok = check_serves(options, receivers); !ok) return std::unexpected(ok.error());
  EXAO_CHECK(geometry != nullptr);
  if (options.offset_default == OffsetDefault::PointScale && !options.origin_offset && options.method == Method::Raster) {
    // The raster volumes are grown by one offset for every pixel (raster/influence_volume.h).
    return fail("origin_offset: the raster method needs one offset for all pixels: give one, or the scene's default");
  }
  if (!geometry->serves(options.method)) {
    return fail(std::string("method: the geometry was not prepared for ") + method_name(options.method));
  }
  if (auto ok = check_serves_cutouts(options, geometry->has_cutouts()); !ok) return std::unexpected(ok.error());
  auto impl = std::make_unique<Impl>();
  impl->options = options;
  impl->options.sidedness = geometry->sidedness();
  impl->options.bvh = geometry->bvh_options();
  impl->served = receivers;
  impl->geometry = std::move(geometry);
  impl->arena = std::make_unique<tbb::task_arena>(options.threads > 0 ? options.threads
                                                                       : static_cast<int>(tbb::task_arena::automatic));
  impl->arena->initialize();

  // Defaults resolved once against the scene's size (engine/options.h).
  const float diagonal = impl->geometry->bounds().diagonal();
  const float radius = options.radius.resolve(diagonal);
  const bool point_scale = !options.origin_offset && options.offset_default == OffsetDefault::PointScale;
  const float offset = options.origin_offset.value_or(point_scale ? kPointOffsetFloor : kDefaultOffsetFraction * diagonal);
  Result<void> built;
  impl->arena->execute([&] {
    Result<SamplePattern> pattern = options.given_pattern
                                        ? Result<SamplePattern>(*options.given_pattern)
                                        : make_sample_pattern(options.samples, options.falloff, options.pattern_seed);
    if (!pattern) {
      built = std::unexpected(pattern.error());
      return;
    }
    Result<ShadowRays> rays = make_shadow_rays(std::move(*pattern), radius, offset);
    if (!rays) {
      built = std::unexpected(rays.error());
      return;
    }
    impl->rays = std::move(*rays);
    if (point_scale) impl->rays.offset_per_magnitude = kPointOffsetFraction;
    if (options.method == Method::Embree) return;
    Result<lut::MaskEngine> masks = lut::MaskEngine::build(impl->rays, options.masks, options.table_resolution, options.isa);
    if (!masks) {
      built = std::unexpected(masks.error());
      return;
    }
    impl->masks = std::move(*masks);
  });
  if (!built) return std::unexpected(built.error());
  return Engine(std::move(impl));
}

const Options& Engine::options() const { return impl_->options; }
const ShadowRays& Engine::rays() const { return impl_->rays; }
const lut::MaskEngine* Engine::mask_engine() const { return impl_->masks ? &*impl_->masks : nullptr; }
const Geometry& Engine::geometry() const { return *impl_->geometry; }
std::shared_ptr<const Geometry> Engine::shared_geometry() const { return impl_->geometry; }
int Engine::threads() const { return impl_->arena->max_concurrency(); }

Result<void> Engine::refit(std::span<const glm::vec3> vertices) {
  // Geometry::build makes every geometry as a non-const object; engines share it read-only, and
  // refit is its one writer (no query may run meanwhile: engine.h).
  const std::shared_ptr<Geometry> geometry = std::const_pointer_cast<Geometry>(impl_->geometry);
  Result<void> done;
  impl_->arena->execute([&] { done = geometry->refit(vertices); });
  return done;
}

Result<void> Engine::run(std::span<const Receiver> receivers, const Outputs& outputs, const RunOptions& run) const {
  const Impl& impl = *impl_;
  if (auto ok = check_serves(impl.options, Receivers::Points); !ok) return ok;
  const std::size_t words = mask_words();
  if (const std::string problem = output_problem(outputs, receivers.size(), words); !problem.empty()) return fail(problem);
  if (receivers.empty()) return {};
  const int n = samples();
  if (!run.supplied_blocked.empty()) {
    // Answers computed before (exao merge): the same formula, no rays.
    if (run.supplied_blocked.size() != receivers.size()) {
      return fail("supplied counts: " + std::to_string(run.supplied_blocked.size()) + " values for " +
                  std::to_string(receivers.size()) + " receivers");
    }
    if (!outputs.masks.empty()) return fail("outputs.masks: masks cannot be made from supplied counts");
    for (std::size_t r = 0; r < receivers.size(); ++r) {
      const std::uint32_t blocked = run.supplied_blocked[r];
      if (blocked > static_cast<std::uint32_t>(n)) {
        return fail("supplied counts: receiver " + std::to_string(r) + " has " + std::to_string(blocked) +
                    " blocked rays of " + std::to_string(n));
      }
      if (!outputs.ao.empty()) outputs.ao[r] = ao_from_blocked(static_cast<int>(blocked), n);
      if (!outputs.blocked.empty()) outputs.blocked[r] = blocked;
    }
    if (run.progress) run.progress(receivers.size(), receivers.size());
    return {};
  }
  if (run.shard && (run.shard->count < 1 || run.shard->index >= run.shard->count)) {
    return fail("shard: part " + std::to_string(run.shard->index) + " of " + std::to_string(run.shard->count) +
                " does not exist");
  }
  const auto [first_chunk, last_chunk] = shard_chunks(receivers.size(), run.shard.value_or(Shard{}));
  if (first_chunk == last_chunk) return {};
  impl.arena->execute([&] {
    // Chunks of the Morton order: each chunk's receivers are neighbours, and only one chunk's
    // masks exist at a time. A shard runs its own chunks only, exactly as the whole batch would.
    const std::vector<std::uint32_t> order = morton_order(receivers);
    std::vector<Receiver> chunk(std::min(kChunk, receivers.size()));
    const std::size_t first = first_chunk * kChunk;
    const std::size_t end = std::min(last_chunk * kChunk, receivers.size());
    for (std::size_t begin = first; begin < end; begin += kChunk) {
      const std::size_t count = std::min(kChunk, receivers.size() - begin);
      for (std::size_t i = 0; i < count; ++i) chunk[i] = receivers[order[begin + i]];
      ProgressCallback progress;
      if (run.progress) {
        progress = [&, begin](std::size_t done, std::size_t) { run.progress(begin - first + done, end - first); };
      }
      const MaskSet masks = impl.backend_masks(std::span<const Receiver>(chunk.data(), count), progress, run);
      EXAO_CHECK_EQ(masks.size(), count);
      for (std::size_t i = 0; i < count; ++i) {
        const std::uint32_t r = order[begin + i];
        const int blocked = masks.blocked_count(i);
        if (!outputs.ao.empty()) outputs.ao[r] = ao_from_blocked(blocked, n);
        if (!outputs.blocked.empty()) outputs.blocked[r] = static_cast<std::uint32_t>(blocked);
        if (!outputs.masks.empty()) std::copy_n(masks.row(i).begin(), words, outputs.masks.begin() + r * words);
      }
    }
  });
  return {};
}

Result<std::vector<float>> Engine::ao(std::span<const Receiver> receivers, const RunOptions& run) const {
  std::vector<float> out(receivers.size());
  Outputs outputs;
  outputs.ao = out;
  if (auto ok = this->run(receivers, outputs, run); !ok) return std::unexpected(ok.error());
  return out;
}

Result<MaskSet> Engine::masks(std::span<const Receiver> receivers, const RunOptions& run) const {
  MaskSet out(receivers.size(), samples());
  Outputs outputs;
  outputs.masks = out.all_rows();
  if (auto ok = this->run(receivers, outputs, run); !ok) return std::unexpected(ok.error());
  return out;
}

void Engine::mask_one(const Receiver& receiver, std::span<std::uint64_t> words) const {
  const Impl& impl = *impl_;
  const std::size_t count = mask_words();
  EXAO_CHECK_EQ(words.size(), count);
  EXAO_CHECK(impl.options.method != Method::Raster);
  if (impl.options.method == Method::Embree) {
    // One receiver: single rays (packets across receivers would have one live lane).
    EmbreeOptions embree = impl.options.embree;
    embree.rays = EmbreeRays::Single;
    const MaskSet set = impl.geometry->embree()->occlusion(impl.rays, std::span<const Receiver>(&receiver, 1), embree);
    std::copy_n(set.row(0).begin(), count, words.begin());
    return;
  }
  const Frame frame = impl.rays.frame(receiver);
  const lut::MaskEngine& engine = impl.masks_for(impl.reach(receiver));
  if (impl.options.method == Method::Auto) {
    bvh::hybrid_mask_one(*impl.geometry->bvh(), engine, *impl.geometry->embree(), receiver, impl.options.hybrid,
                         *impl.hybrid, words);
    return;
  }
  with_mask_bits(samples(), [&](auto bits) {
    constexpr int Bits = decltype(bits)::value;
    const lut::FlushDenormals flush;  // the same float mode on every thread (lut/float_mode.h)
    Mask<Bits> mask;
    if (impl.options.method == Method::Bvh) {
      mask = bvh::traverse<Bits, false>(*impl.geometry->bvh(), engine, frame, nullptr);
    } else {
      // brute's definition, without the grid a batch builds: every triangle.
      const lut::TriangleSet& triangles = *impl.geometry->triangles();
      mask = lut::brute_mask<Bits>(engine, triangles, frame,
                                   std::views::iota(std::uint32_t{0}, static_cast<std::uint32_t>(triangles.size())));
    }
    std::copy_n(mask.words.begin(), count, words.begin());
  });
}

Result<PixelReceivers> Engine::pixel_receivers(const Camera& camera, int width, int height) const {
  const Impl& impl = *impl_;
  if (!impl.geometry->embree() || !impl.geometry->scene()) {
    return fail("method: this engine's geometry has no Embree scene for primary visibility (build it for pixels)");
  }
  PixelReceivers out;
  impl.arena->execute(
      [&] { out = exao::pixel_receivers(*impl.geometry->embree(), *impl.geometry->scene(), camera, width, height); });
  return out;
}

Result<MaskSet> Engine::pixel_masks(const PixelReceivers& pixels, const Camera& camera, const RunOptions& run) const {
  const Impl& impl = *impl_;
  if (auto ok = check_serves(impl.options, Receivers::Pixels); !ok) return std::unexpected(ok.error());
  if (impl.options.method != Method::Raster) return masks(pixels.receivers, run);
  if (run.shard || !run.supplied_blocked.empty()) {
    return fail("method: raster computes a camera's whole image at once and cannot be sharded; use bvh, brute or embree");
  }
  Result<std::optional<LodLevels>> lod = prepare_lod(pixels, camera);
  if (!lod) return std::unexpected(lod.error());
  raster::RasterOptions options = impl.options.raster;
  options.stats = run.stats != nullptr;
  // With levels of detail the triangles are every level's, each with its distance range.
  const lut::TriangleSet* triangles = impl.geometry->triangles();
  if (*lod) {
    triangles = &(*lod)->levels->triangles;
    options.ranges = (*lod)->levels->ranges;
  }
  raster::RasterResult result;
  impl.arena->execute([&] {
    result = raster::occlusion(pixels, *impl.geometry->scene(), *triangles, impl.masks_for(pixels.receivers), camera,
                               options, run.progress);
  });
  if (run.stats) run.stats->raster += result.stats;
  return std::move(result.masks);
}

Result<std::optional<LodLevels>> Engine::prepare_lod(const PixelReceivers& pixels, const Camera& camera,
                                                     const ProgressCallback& progress) const {
  const Impl& impl = *impl_;
  if (!impl.options.lod) return std::optional<LodLevels>{};
  if (auto ok = check_serves(impl.options, Receivers::Pixels); !ok) return std::unexpected(ok.error());
  LodCache* cache = impl.geometry->lod_cache();
  EXAO_CHECK(cache != nullptr);  // a geometry that serves raster has one
  LodLevels out;
  out.automatic = impl.options.lod->eps1 == 0.0f;
  out.options = resolve_lod(*impl.options.lod, radius(), pixel_footprint(pixels, camera));
  Result<LodCache::Entry> entry;
  impl.arena->execute([&] { entry = cache->get(radius(), out.options, progress); });
  if (!entry) return std::unexpected(entry.error());
  out.levels = entry->levels;
  out.built = entry->built;
  return std::optional<LodLevels>{out};
}

Result<PixelReceivers> Engine::render_pixels(const Camera& camera, int width, int height) const {
  const Impl& impl = *impl_;
  if (auto ok = check_serves(impl.options, Receivers::Pixels); !ok) return std::unexpected(ok.error());
  if (impl.options.method != Method::Raster) return pixel_receivers(camera, width, height);
  // Its own G-buffer: primary visibility by the same rasteriser that draws the volumes.
  PixelReceivers out;
  impl.arena->execute([&] { out = raster::raster_pixel_receivers(*impl.geometry->scene(), camera, width, height); });
  return out;
}

Result<PixelResult> Engine::render(const Camera& camera, int width, int height, const RunOptions& run) const {
  PixelResult out;
  Result<PixelReceivers> pixels = render_pixels(camera, width, height);
  if (!pixels) return std::unexpected(pixels.error());
  out.pixels = std::move(*pixels);
  Result<MaskSet> masks = pixel_masks(out.pixels, camera, run);
  if (!masks) return std::unexpected(masks.error());
  out.masks = std::move(*masks);
  return out;
}

}  // namespace exao::engine
