// exao bench: every method on the same receivers and rays, timed side by side, compared with
// Embree ray for ray. A table on stdout, optionally JSON and an SVG bar chart.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>
#include <optional>
#include <sstream>

#include "bake/bake.h"
#include "bake/document.h"
#include "cli/bench_report.h"
#include "cli/commands.h"
#include "cli/common_options.h"
#include "cli/lod_options.h"
#include "cli/progress_bar.h"
#include "core/ao_error.h"
#include "core/atomic_write.h"
#include "io/image_io.h"
#include "core/isa.h"
#include "core/pixel_receivers.h"
#include "engine/engine.h"

namespace exao::cli {
namespace {

struct BenchOptions {
  SceneOptions scene;
  RayOptions rays;
  CameraOptions camera;
  MethodOptions method;
  std::vector<int> samples{128, 1024};
  std::vector<std::string> radii{"1%", "5%"};
  std::vector<std::string> methods{"embree", "auto", "bvh"};
  std::vector<std::string> masks{"lut", "exact"};
  std::vector<std::string> embree_rays{"packet16"};
  std::vector<std::string> isas{"auto"};
  std::string receivers = "pixels";  // pixels, vertices, or texels:SIZE[:SAMPLES]
  std::vector<std::string> lod{"off"};  // raster+lod rows: auto, or eps_1 values; off: none
  LodCliOptions lod_settings;
  int repeats = 1;
  std::string json;
  std::string svg;
  std::string markdown;
  std::string label;
  std::string png_dir;  // a PNG preview of every row's AO, for pictures and by-eye checks
  bool stats = false;
  ShardCliOptions shard;
};

// How a method's masks compare with Embree's on the same rays.
void compare(const MaskSet& reference, const MaskSet& masks, BenchRun& run) {
  std::uint64_t agree = 0;
  std::size_t identical = 0;
  double sum_error = 0.0, max_error = 0.0;
  const std::uint64_t rays = static_cast<std::uint64_t>(reference.size()) * static_cast<std::uint64_t>(reference.samples());
  for (std::size_t i = 0; i < reference.size(); ++i) {
    const auto a = reference.row(i);
    const auto b = masks.row(i);
    int differ = 0;
    for (std::size_t w = 0; w < a.size(); ++w) differ += std::popcount(a[w] ^ b[w]);
    agree += static_cast<std::uint64_t>(reference.samples() - differ);
    const double error = std::abs(static_cast<double>(reference.ao(i)) - static_cast<double>(masks.ao(i)));
    identical += reference.blocked_count(i) == masks.blocked_count(i);
    sum_error += error;
    max_error = std::max(max_error, error);
  }
  run.ray_agreement = rays ? static_cast<double>(agree) / static_cast<double>(rays) : 1.0;
  run.identical_receivers = reference.size() ? static_cast<double>(identical) / static_cast<double>(reference.size()) : 1.0;
  run.mean_abs_error = reference.size() ? sum_error / static_cast<double>(reference.size()) : 0.0;
  run.max_abs_error = max_error;
}

// The bake whose receivers --receivers asks for (vertex or texel); checked before the scene is read.
Result<bake::BakeOptions> receivers_bake(const std::string& spec) {
  bake::BakeOptions options;
  if (spec == "vertices") {
    options.target = bake::Target::Vertex;
  } else if (spec.rfind("texels:", 0) == 0) {
    options.target = bake::Target::Texture;
    int size = 0, samples = 1;
    if (std::sscanf(spec.c_str() + 7, "%d:%d", &size, &samples) < 1) {
      return fail("--receivers: '" + spec + "' is not texels:SIZE[:SAMPLES]");
    }
    options.texture_size = size;
    options.texel_samples = samples;
  } else {
    return fail("--receivers: '" + spec + "' is not pixels, vertices or texels:SIZE[:SAMPLES]");
  }
  if (auto ok = bake::check_options(options); !ok) {
    return fail("--receivers " + spec + ": " + ok.error().message);
  }
  return options;
}

// One timed configuration of a (N, r): a method with a mask mode and instruction set, or Embree
// with a ray mode.
struct Config {
  engine::Method method;
  lut::MaskMode mode;
  EmbreeRays rays;
  std::optional<Isa> isa;
  int lod = -1;  // raster+lod: index into BenchLists::lods
};

// The lists of --methods, --masks, --embree-rays and --isa, each checked against what the methods
// serve (on a camera's pixels, or on points for a bake's receivers).
struct BenchLists {
  std::vector<engine::Method> methods;  // embree first: the reference of every comparison
  std::vector<lut::MaskMode> modes;
  std::vector<EmbreeRays> embree_modes;
  std::vector<Isa> isas;                // resolved: every one runs on this CPU
  std::vector<raster::LodOptions> lods;  // raster+lod rows, for every raster row (eps1 0: auto)
};

Result<BenchLists> parse_lists(const BenchOptions& options, const engine::Options& base, engine::Receivers receivers) {
  BenchLists out;
  out.methods.push_back(engine::Method::Embree);
  for (const std::string& name : options.methods) {
    Result<engine::Method> m = engine::parse_method(name);
    if (!m) return std::unexpected(m.error());
    if (std::find(out.methods.begin(), out.methods.end(), *m) == out.methods.end()) out.methods.push_back(*m);
  }
  for (const std::string& name : options.masks) {
    Result<lut::MaskMode> m = lut::parse_mask_mode(name);
    if (!m) return std::unexpected(m.error());
    out.modes.push_back(*m);
  }
  for (const std::string& name : options.embree_rays) {
    Result<EmbreeRays> r = parse_embree_rays(name);
    if (!r) return std::unexpected(r.error());
    out.embree_modes.push_back(*r);
  }
  if (out.embree_modes.empty()) return fail("embree.rays: give at least one mode");
  for (const std::string& name : options.isas) {
    Result<std::optional<Isa>> parsed = parse_isa(name);
    if (!parsed) return std::unexpected(parsed.error());
    Result<Isa> level = resolve_isa(*parsed);
    if (!level) return std::unexpected(level.error());
    out.isas.push_back(*level);
  }
  if (out.isas.empty()) return fail("isa: give at least one instruction set");
  for (const int n : options.samples) {
    if (auto ok = check_sample_count(n); !ok) return std::unexpected(ok.error());
  }
  for (const engine::Method m : out.methods) {
    for (const lut::MaskMode mode : out.modes) {
      if (m == engine::Method::Auto && mode != lut::MaskMode::Exact) continue;  // one exact row
      engine::Options o = base;
      o.method = m;
      o.masks = mode;
      if (auto ok = engine::check_serves(o, receivers); !ok) return std::unexpected(ok.error());
    }
  }
  // Levels of detail: one raster+lod row per --lod value and raster row; none without raster.
  const bool raster = std::find(out.methods.begin(), out.methods.end(), engine::Method::Raster) != out.methods.end();
  for (const std::string& spec : options.lod) {
    LodCliOptions cli = options.lod_settings;
    cli.lod = spec;
    Result<std::optional<raster::LodOptions>> lod = parse_lod(cli);
    if (!lod) return std::unexpected(lod.error());
    if (!*lod || !raster) continue;
    engine::Options o = base;
    o.method = engine::Method::Raster;
    o.lod = *lod;
    if (auto ok = engine::check_options(o); !ok) return std::unexpected(ok.error());
    out.lods.push_back(**lod);
  }
  return out;
}

int run_bench(const BenchOptions& options, const Invocation&) {
  if (options.repeats < 1) return report(Error{"--repeats: must be at least 1, got " + std::to_string(options.repeats)});
  Result<std::optional<engine::Shard>> shard = resolve_shard(options.shard);
  if (!shard) return report(shard.error());
  if (*shard && options.receivers == "pixels") {
    return report(Error{"--shard: only with --receivers vertices or texels:SIZE (a bake's receivers, cut into chunks)"});
  }
  Result<engine::Options> base = make_options(options.scene, options.rays, options.method);
  if (!base) return report(base.error());
  print_thread_note(base->threads);
  // Pixel receivers come from the scene as every command loads it; bake receivers from the
  // scene as the bake reads it (a glTF's default scene, or the soup converted with an atlas).
  const bool on_pixels = options.receivers == "pixels";
  const engine::Receivers kind = on_pixels ? engine::Receivers::Pixels : engine::Receivers::Points;
  Result<BenchLists> lists = parse_lists(options, *base, kind);
  if (!lists) return report(lists.error(), {{"method", "--methods"}});

  std::optional<bake::Document> document;
  std::optional<bake::BakeOptions> bake_options;
  Result<Scene> scene = fail("no scene");
  if (on_pixels) {
    scene = open_scene(options.scene);
  } else {
    Result<bake::BakeOptions> planned = receivers_bake(options.receivers);
    if (!planned) return report(planned.error());
    bake_options = *planned;
    // A mesh without UVs gets a box-projection atlas laid out for this map size, as in exao bake.
    bake::ConvertOptions convert;
    if (bake_options->target == bake::Target::Texture) {
      convert.atlas_size = bake_options->texture_size;
      convert.atlas_padding = 2 * bake_options->margin + 2;
    }
    Result<bake::Document> opened = bake::Document::open(options.scene.scene, convert);
    if (!opened) return report(opened.error());
    document = std::move(*opened);
    scene = document->scene();
  }
  if (!scene) return report(scene.error());
  Result<View> view = choose_view(options.camera, *scene);
  if (!view) return report(view.error());
  // One geometry (Embree scene, triangles, BVH) for every engine of the run.
  engine::GeometryOptions geometry_options;
  geometry_options.sidedness = base->sidedness;
  geometry_options.cutouts = base->cutouts;
  geometry_options.bvh = base->bvh;
  geometry_options.embree = true;
  geometry_options.threads = base->threads;
  Result<std::shared_ptr<const engine::Geometry>> geometry =
      engine::Geometry::build(*scene, lists->methods, geometry_options);
  if (!geometry) return report(geometry.error());
  const auto engine_for = [&](engine::Method method, lut::MaskMode mode, std::optional<Isa> isa, int n,
                              const std::string& radius, int lod = -1) {
    engine::Options o = *base;
    o.method = method;
    if (lod >= 0) o.lod = lists->lods[static_cast<std::size_t>(lod)];
    o.masks = mode;
    o.isa = isa;
    o.samples = n;
    Result<engine::Length> r = parse_radius(radius);
    if (!r) return Result<engine::Engine>(std::unexpected(r.error()));
    o.radius = *r;
    return engine::Engine::build(*geometry, o, kind);
  };
  // Every method runs on the same receivers (Embree's pixels, or the bake's), so that all cast
  // the same rays.
  Result<engine::Engine> reference = engine_for(engine::Method::Embree, lut::MaskMode::Exact, std::nullopt,
                                                options.samples.front(),
                                                options.radii.empty() ? std::string() : options.radii.front());
  if (!reference) return report(reference.error());
  Result<PixelReceivers> pixels = PixelReceivers{};
  if (on_pixels) {
    pixels = reference->pixel_receivers(view->camera, view->width, view->height);
    if (!pixels) return report(pixels.error());
    if (pixels->receivers.empty()) return report(Error{options.scene.scene + ": the camera sees no triangle; try --eye/--target"});
  } else {
    Result<std::vector<Receiver>> receivers = bake::bake_receivers(*document, *bake_options);
    if (!receivers) return report(receivers.error());
    if (receivers->empty()) return report(Error{options.scene.scene + ": the bake has no receivers"});
    if (*shard) {
      // The shard's receivers only (the chunks a sharded bake computes), in the engine's order:
      // each receiver's rays are the same, so every method is timed on exactly this part.
      const std::size_t total = receivers->size();
      std::vector<Receiver> part;
      for (const std::uint32_t r : engine::shard_receivers(*receivers, **shard)) part.push_back((*receivers)[r]);
      std::printf("shard %zu/%zu: %zu of %zu receivers\n", (*shard)->index, (*shard)->count, part.size(), total);
      if (part.empty()) return report(Error{"--shard: part " + std::to_string((*shard)->index) + " of " +
                                            std::to_string((*shard)->count) + " has no receivers (" +
                                            std::to_string(total) + " receivers make fewer chunks than parts)"});
      *receivers = std::move(part);
    }
    pixels->receivers = std::move(*receivers);
    pixels->width = static_cast<int>(pixels->receivers.size());
    pixels->height = 1;
  }

  BenchReport report_data;
  report_data.scene = options.scene.scene;
  report_data.label = options.label.empty() ? options.scene.scene + " " + options.receivers : options.label;
  if (*shard) report_data.label += " shard " + std::to_string((*shard)->index) + "/" + std::to_string((*shard)->count);
  report_data.triangles = scene->triangle_count();
  report_data.receivers = pixels->receivers.size();
  report_data.threads = reference->threads();
  report_data.width = pixels->width;
  report_data.height = pixels->height;
  print_bench_header(report_data);

  for (const int n : options.samples) {
    for (const std::string& radius_text : options.radii) {
      // The configurations of this (N, r): Embree first, the reference for every comparison.
      std::vector<Config> configs;
      for (const EmbreeRays r : lists->embree_modes) {
        configs.push_back({engine::Method::Embree, lut::MaskMode::Exact, r, std::nullopt});
      }
      for (const engine::Method m : lists->methods) {
        if (m == engine::Method::Embree) continue;
        for (const lut::MaskMode mode : lists->modes) {
          // auto has exact masks only: one row, whatever --masks lists.
          if (m == engine::Method::Auto && mode != lut::MaskMode::Exact) continue;
          for (const Isa isa : lists->isas) configs.push_back({m, mode, EmbreeRays::Single, isa});
        }
      }
      for (const lut::MaskMode mode : lists->modes) {
        for (const Isa isa : lists->isas) {
          for (std::size_t l = 0; l < lists->lods.size(); ++l) {
            configs.push_back({engine::Method::Raster, mode, EmbreeRays::Single, isa, static_cast<int>(l)});
          }
        }
      }
      std::vector<engine::Engine> engines;
      for (const Config& config : configs) {
        Result<engine::Engine> built = engine_for(config.method, config.mode, config.isa, n, radius_text, config.lod);
        if (!built) return report(built.error());
        engines.push_back(std::move(*built));
      }
      // Each radius once: it does not depend on N.
      if (n == options.samples.front()) print_ray_notes(engines.front());
      std::vector<BenchRun> runs(configs.size());
      std::vector<MaskSet> results(configs.size());
      // Interleaved repeats: drift of the machine hits every method alike; the fastest counts.
      for (int repeat = 0; repeat < options.repeats; ++repeat) {
        for (std::size_t c = 0; c < configs.size(); ++c) {
          const Config& config = configs[c];
          engine::Stats stats;
          // The levels of detail: built before the clock starts, once per radius and options
          // (the geometry keeps them for every repeat, N and engine), and said when built.
          std::optional<engine::LodLevels> lod;
          if (config.lod >= 0) {
            Result<std::optional<engine::LodLevels>> levels = std::optional<engine::LodLevels>{};
            {
              ProgressBar lod_bar("lod");
              levels = engines[c].prepare_lod(*pixels, view->camera, lod_bar.callback());
            }
            if (!levels) return report(levels.error());
            lod = *levels;
            if (lod->built) std::printf("%s\n", describe_lod(*lod).c_str());
          }
          const std::string method = lod ? "raster+lod" : engine::method_name(config.method);
          ProgressBar bar("bench " + method);
          engine::RunOptions run;
          run.progress = bar.callback();
          if (options.stats) run.stats = &stats;
          if (config.method == engine::Method::Embree) run.embree_rays = config.rays;
          const auto start = std::chrono::steady_clock::now();
          Result<MaskSet> masks =
              on_pixels ? engines[c].pixel_masks(*pixels, view->camera, run) : engines[c].masks(pixels->receivers, run);
          const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
          bar.finish();
          if (!masks) return report(masks.error());
          BenchRun& r = runs[c];
          if (repeat == 0 || seconds < r.seconds) r.seconds = seconds;
          if (repeat == 0) {
            r.samples = n;
            r.radius = engines[c].radius();
            r.radius_text = radius_text;
            r.method = method;
            if (lod) {
              r.lod_eps1 = lod->options.eps1;
              r.lod_levels = lod->options.levels;
              r.lod_k = lod->options.k;
              r.lod_build_seconds = lod->levels->seconds;
            }
            r.masks = config.method == engine::Method::Embree ? embree_rays_name(config.rays) : lut::mask_mode_name(config.mode);
            const lut::MaskEngine* masks_engine = engines[c].mask_engine();
            r.isa = masks_engine ? isa_name(masks_engine->isa()) : "";
            r.stats = stats;
            results[c] = std::move(*masks);
          }
        }
      }
      for (std::size_t c = 0; c < configs.size(); ++c) {
        BenchRun& run = runs[c];
        run.mrays_per_s = static_cast<double>(pixels->receivers.size()) * n / run.seconds * 1e-6;
        run.speedup_vs_embree = runs[0].seconds / run.seconds;
        compare(results[0], results[c], run);
        const AoError vs_embree = ao_error(results[0], results[c]);
        run.bias = vs_embree.bias();
        run.identical_8bit = vs_embree.identical_8bit_share();
        if (configs[c].lod >= 0) {
          // LOD's own error: against raster without LOD, same masks and instruction set.
          for (std::size_t b = 0; b < configs.size(); ++b) {
            if (configs[b].method != engine::Method::Raster || configs[b].lod >= 0 || configs[b].mode != configs[c].mode ||
                configs[b].isa != configs[c].isa) {
              continue;
            }
            const AoError own = ao_error(results[b], results[c]);
            run.lod_speedup_vs_raster = runs[b].seconds / run.seconds;
            run.lod_mean_abs_vs_raster = own.mean_abs();
            run.lod_max_abs_vs_raster = own.max_abs;
            run.lod_bias_vs_raster = own.bias();
            run.lod_identical_8bit_vs_raster = own.identical_8bit_share();
          }
        }
        print_bench_row(run, options.stats);
        if (!options.png_dir.empty()) {
          AoImage image;
          image.width = pixels->width;
          image.height = pixels->height;
          image.ao.assign(static_cast<std::size_t>(pixels->width) * static_cast<std::size_t>(pixels->height), 1.0f);
          image.coverage.assign(image.ao.size(), 0.0f);
          for (std::size_t r = 0; r < pixels->receivers.size(); ++r) {
            const std::size_t at = on_pixels ? pixels->pixel[r] : r;  // bake receivers: one row
            image.ao[at] = results[c].ao(r);
            image.coverage[at] = 1.0f;
          }
          std::string name = "/" + std::to_string(n) + "-" + radius_text + "-" + run.method + "-" + run.masks;
          if (!run.isa.empty()) name += "-" + run.isa;
          if (configs[c].lod >= 0) name += "-" + std::to_string(run.lod_eps1);
          if (auto ok = write_png(image, options.png_dir + name + ".png"); !ok) return report(ok.error());
        }
        report_data.runs.push_back(run);
      }
    }
  }
  if (!options.json.empty()) {
    if (auto ok = write_bench_json(report_data, options.json); !ok) return report(ok.error());
  }
  if (!options.svg.empty()) {
    if (auto ok = write_bench_svg(report_data, options.svg); !ok) return report(ok.error());
  }
  if (!options.markdown.empty()) {
    if (auto ok = write_bench_markdown(report_data, options.markdown); !ok) return report(ok.error());
  }
  return 0;
}

}  // namespace

Command add_bench_command(CLI::App& app) {
  auto options = std::make_shared<BenchOptions>();
  options->camera.width = 512;
  options->camera.height = 384;
  CLI::App* command = app.add_subcommand("bench", "Time every method on a camera's pixels against Embree on the same rays");
  add_scene_options(*command, options->scene);
  add_camera_options(*command, options->camera);
  command->add_option("-n,--samples", options->samples, "Rays per receiver, a list: 128,1024")->delimiter(',')->capture_default_str();
  command->add_option("-r,--radius", options->radii, "Radii, a list of lengths or percentages: 1%,5%")->delimiter(',')->capture_default_str();
  command->add_option("--methods", options->methods, "Methods to time besides embree: auto, brute, bvh, raster (raster on Embree's pixel receivers)")->delimiter(',')->capture_default_str();
  command->add_option("--hybrid", options->method.hybrid,
                      "auto's split: adaptive (its cost model), masks (masks to the end) or rays (Embree only)")
      ->capture_default_str();
  command->add_option("--masks", options->masks, "Mask modes, a list: lut,exact")->delimiter(',')->capture_default_str();
  command->add_option("--falloff", options->rays.falloff, "constant, linear or quadratic")->capture_default_str();
  command->add_option("--offset", options->rays.offset, "Ray origin offset (default 1e-4 of the diagonal)");
  command->add_option("-j,--threads", options->rays.threads, "Worker threads (0: all cores)")->capture_default_str();
  command->add_option("--embree-rays", options->embree_rays,
                      "Embree modes, a list of single, packet4, packet8, packet16; the first is the reference")
      ->delimiter(',')
      ->capture_default_str();
  command->add_flag("--embree-per-receiver", options->method.embree_per_receiver,
                    "Embree packets hold neighbouring samples of one receiver");
  command->add_option("--table-resolution", options->method.table_resolution, "Look-up table cells per side (0: default)");
  command->add_option("--branching", options->method.branching, "BVH children per node: 2 or 4")->capture_default_str();
  command->add_option("--leaf-size", options->method.leaf_size, "Most triangles per BVH leaf: 1 to 8")->capture_default_str();
  command->add_option("--receivers", options->receivers,
                      "Receivers: pixels (of the camera), vertices (of a vertex bake) or texels:SIZE[:SAMPLES] "
                      "(of a texture bake, SAMPLES per texel, default 1)")
      ->capture_default_str();
  command->add_option("--lod", options->lod,
                      "raster+lod rows (paper Sec. 4.3), a list of auto or eps_1 lengths (ascending: the smallest "
                      "eps_1 3^j serves the rest); off: none")
      ->delimiter(',')
      ->capture_default_str();
  command->add_option("--lod-levels", options->lod_settings.levels, "Simplified levels, 1 to 8")->capture_default_str();
  command->add_option("--lod-k", options->lod_settings.k, "Level i serves distances [k eps_i, k eps_(i+1)]")->capture_default_str();
  command->add_option("--lod-overlap", options->lod_settings.overlap, "Level i starts at (k - overlap) eps_i")->capture_default_str();
  command->add_option("--lod-filter", options->lod_settings.filter, "envelope or distance")->capture_default_str();
  command->add_option("--repeats", options->repeats, "Interleaved repeats; the fastest time counts")->capture_default_str();
  command->add_option("--isa", options->isas,
                      "Instruction sets of the mask kernels, a list of auto, scalar, sse2, sse4, avx2, avx512 "
                      "(auto: EXAO_ISA, else the best this CPU runs)")
      ->delimiter(',')
      ->capture_default_str();
  command->add_option("--json", options->json, "Write the results as JSON");
  command->add_option("--svg", options->svg, "Write a bar chart of Mrays/s as SVG");
  command->add_option("--markdown", options->markdown, "Write the results as a Markdown table");
  command->add_option("--label", options->label, "The workload's name in the tables (default: scene and receivers)");
  command->add_option("--png-dir", options->png_dir, "Write every row's AO as a PNG preview into this folder");
  command->add_flag("--stats", options->stats, "Add BVH work counters per receiver");
  add_shard_options(*command, options->shard, false);
  return [options, command](const Invocation& invocation) { return command->parsed() ? run_bench(*options, invocation) : -1; };
}

}  // namespace exao::cli
