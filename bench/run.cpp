#include "bench/run.h"

#include <chrono>
#include <utility>

#include "bake/bake.h"
#include "bench/ratios.h"
#include "core/isa.h"

namespace exao::bench {
namespace {

Result<engine::Engine> row_engine(const Plan& plan, const Setup& setup, const Config& config, int samples,
                                  const engine::Length& radius) {
  const engine::Receivers kind = plan.bake ? engine::Receivers::Points : engine::Receivers::Pixels;
  return engine::Engine::build(setup.geometry, row_options(plan, config, samples, radius), kind);
}

// The bake's receivers, or the shard's part of them (the chunks a sharded bake computes) in the
// engine's order: each receiver's rays are the same, so every method is timed on exactly this part.
Result<void> choose_bake_receivers(const Plan& plan, Workload& workload, Setup& setup) {
  Result<std::vector<Receiver>> receivers = bake::bake_receivers(*workload.document, *plan.bake);
  if (!receivers) return std::unexpected(receivers.error());
  if (receivers->empty()) return fail(workload.name + ": the bake has no receivers");
  setup.all_receivers = receivers->size();
  if (plan.shard) {
    std::vector<Receiver> part;
    for (const std::uint32_t r : engine::shard_receivers(*receivers, *plan.shard)) part.push_back((*receivers)[r]);
    *receivers = std::move(part);
  }
  setup.receivers.receivers = std::move(*receivers);
  setup.receivers.width = static_cast<int>(setup.receivers.receivers.size());
  setup.receivers.height = 1;
  return {};
}

// One timed row: the fastest of the repeats goes into `run` by the caller; this times one.
struct Timed {
  double seconds = 0.0;
  MaskSet masks;
  engine::Stats stats;
  std::optional<engine::LodLevels> lod;
};

// The levels of detail of a raster+lod row: built before the clock starts, once per radius and
// options (the geometry keeps them for every repeat, N and engine), and told when built.
Result<std::optional<engine::LodLevels>> prepare_row_lod(const engine::Engine& engine, const Workload& workload,
                                                        const Setup& setup, const Events& events) {
  ProgressCallback progress = events.progress_started ? events.progress_started("lod") : ProgressCallback{};
  Result<std::optional<engine::LodLevels>> levels = engine.prepare_lod(setup.receivers, workload.camera, progress);
  if (events.progress_finished) events.progress_finished();
  if (!levels) return levels;
  if (*levels && (*levels)->built && events.lod_built) events.lod_built(**levels);
  return levels;
}

Result<Timed> time_row(const Plan& plan, const Workload& workload, const Setup& setup, const Config& config,
                       const engine::Engine& engine, const Events& events) {
  Timed timed;
  if (config.lod >= 0) {
    Result<std::optional<engine::LodLevels>> levels = prepare_row_lod(engine, workload, setup, events);
    if (!levels) return std::unexpected(levels.error());
    timed.lod = *levels;
  }
  const std::string method = timed.lod ? "raster+lod" : engine::method_name(config.method);
  engine::RunOptions options;
  if (events.progress_started) options.progress = events.progress_started("bench " + method);
  if (plan.stats) options.stats = &timed.stats;
  if (config.method == engine::Method::Embree) options.embree_rays = config.rays;
  const auto start = std::chrono::steady_clock::now();
  Result<MaskSet> masks = plan.bake ? engine.masks(setup.receivers.receivers, options)
                                    : engine.pixel_masks(setup.receivers, workload.camera, options);
  timed.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (events.progress_finished) events.progress_finished();
  if (!masks) return std::unexpected(masks.error());
  timed.masks = std::move(*masks);
  return timed;
}

// What a row is, from its first repeat: N, r, the names of its method, masks and kernels, LOD.
Run describe_row(const Config& config, const engine::Engine& engine, int samples, const Radius& radius,
                 const Timed& timed) {
  Run r;
  r.samples = samples;
  r.radius = engine.radius();
  r.radius_text = radius.text;
  r.method = timed.lod ? "raster+lod" : engine::method_name(config.method);
  if (timed.lod) {
    r.lod_eps1 = timed.lod->options.eps1;
    r.lod_levels = timed.lod->options.levels;
    r.lod_k = timed.lod->options.k;
    r.lod_build_seconds = timed.lod->levels->seconds;
  }
  r.masks = config.method == engine::Method::Embree ? embree_rays_name(config.rays) : lut::mask_mode_name(config.mode);
  const lut::MaskEngine* masks_engine = engine.mask_engine();
  r.isa = masks_engine ? isa_name(masks_engine->isa()) : "";
  r.stats = timed.stats;
  return r;
}

// Every row of one (N, r), timed and compared with the first.
Result<void> run_group(const Plan& plan, const Workload& workload, const Setup& setup, int samples,
                       const Radius& radius, const Events& events, Report& report) {
  const std::vector<Config> configs = configurations(plan);
  std::vector<engine::Engine> engines;
  for (const Config& config : configs) {
    Result<engine::Engine> built = row_engine(plan, setup, config, samples, radius.length);
    if (!built) return std::unexpected(built.error());
    engines.push_back(std::move(*built));
  }
  // Each radius once: it does not depend on N.
  if (samples == plan.samples.front() && events.radius_ready) events.radius_ready(engines.front());
  std::vector<Run> runs(configs.size());
  std::vector<MaskSet> results(configs.size());
  // Interleaved repeats: drift of the machine hits every method alike; the fastest counts.
  for (int repeat = 0; repeat < plan.repeats; ++repeat) {
    for (std::size_t c = 0; c < configs.size(); ++c) {
      Result<Timed> timed = time_row(plan, workload, setup, configs[c], engines[c], events);
      if (!timed) return std::unexpected(timed.error());
      if (repeat == 0) {
        runs[c] = describe_row(configs[c], engines[c], samples, radius, *timed);
        runs[c].seconds = timed->seconds;
        results[c] = std::move(timed->masks);
      } else if (timed->seconds < runs[c].seconds) {
        runs[c].seconds = timed->seconds;
      }
    }
  }
  add_ratios(runs, results, configs, setup.receivers.receivers.size());
  for (std::size_t c = 0; c < configs.size(); ++c) {
    if (events.row) {
      if (auto ok = events.row(runs[c], results[c]); !ok) return ok;
    }
    report.runs.push_back(runs[c]);
  }
  return {};
}

}  // namespace

Result<bake::Document> open_document(const std::string& name_or_path, const bake::BakeOptions& bake) {
  bake::ConvertOptions convert;
  if (bake.target == bake::Target::Texture) {
    convert.atlas_size = bake.texture_size;
    convert.atlas_padding = 2 * bake.margin + 2;
  }
  return bake::Document::open(name_or_path, convert);
}

Result<Setup> prepare(const Plan& plan, Workload& workload) {
  Setup setup;
  // One geometry (Embree scene, triangles, BVH) for every engine of the run.
  engine::GeometryOptions geometry;
  geometry.sidedness = plan.base.sidedness;
  geometry.cutouts = plan.base.cutouts;
  geometry.bvh = plan.base.bvh;
  geometry.embree = true;
  geometry.threads = plan.base.threads;
  Result<std::shared_ptr<const engine::Geometry>> built = engine::Geometry::build(workload.scene, plan.methods, geometry);
  if (!built) return std::unexpected(built.error());
  setup.geometry = std::move(*built);
  // Every method runs on the same receivers (Embree's pixels, or the bake's), so that all cast
  // the same rays.
  const Config reference_row{engine::Method::Embree, lut::MaskMode::Exact, EmbreeRays::Single, std::nullopt};
  Result<engine::Engine> reference = row_engine(plan, setup, reference_row, plan.samples.front(),
                                                plan.radii.empty() ? plan.base.radius : plan.radii.front().length);
  if (!reference) return std::unexpected(reference.error());
  setup.reference = std::move(*reference);
  if (plan.bake) {
    if (auto ok = choose_bake_receivers(plan, workload, setup); !ok) return std::unexpected(ok.error());
  } else {
    Result<PixelReceivers> pixels = setup.reference->pixel_receivers(workload.camera, workload.width, workload.height);
    if (!pixels) return std::unexpected(pixels.error());
    setup.receivers = std::move(*pixels);
    setup.all_receivers = setup.receivers.receivers.size();
  }
  setup.report.scene = workload.name;
  setup.report.label = plan.label;
  setup.report.triangles = workload.scene.triangle_count();
  setup.report.receivers = setup.receivers.receivers.size();
  setup.report.threads = setup.reference->threads();
  setup.report.width = setup.receivers.width;
  setup.report.height = setup.receivers.height;
  return setup;
}

Result<void> check_receivers(const Plan& plan, const Workload& workload, const Setup& setup) {
  if (!setup.receivers.receivers.empty()) return {};
  if (!plan.bake) return fail(workload.name + ": the camera sees no triangle");
  if (plan.shard) {
    return fail("shard: part " + std::to_string(plan.shard->index) + " of " + std::to_string(plan.shard->count) +
                " has no receivers (" + std::to_string(setup.all_receivers) + " receivers make fewer chunks than parts)");
  }
  return fail(workload.name + ": the bake has no receivers");
}

Result<Report> run(const Plan& plan, const Workload& workload, const Setup& setup, const Events& events) {
  if (auto ok = check_receivers(plan, workload, setup); !ok) return std::unexpected(ok.error());
  Report report = setup.report;
  for (const int n : plan.samples) {
    for (const Radius& radius : plan.radii) {
      if (auto ok = run_group(plan, workload, setup, n, radius, events, report); !ok) return std::unexpected(ok.error());
    }
  }
  return report;
}

}  // namespace exao::bench
