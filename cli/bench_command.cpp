// exao bench: every method on the same receivers and rays, timed side by side, compared with
// Embree ray for ray (the library's bench::run). A table on stdout, optionally JSON, Markdown and
// an SVG bar chart, and a PNG of every row.

#include <cstdio>
#include <memory>
#include <optional>
#include <string>

#include "bake/options.h"
#include "bench/plan.h"
#include "bench/run.h"
#include "cli/bench_report.h"
#include "cli/commands.h"
#include "cli/common_options.h"
#include "cli/lod_options.h"
#include "cli/progress_bar.h"
#include "core/isa.h"
#include "core/mask_set.h"
#include "core/pixel_receivers.h"
#include "engine/engine.h"
#include "io/image_io.h"

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

// The lists of --methods, --masks, --embree-rays, --isa, --lod, -n and -r as the library's plan
// (its checks are bench::check_plan's).
Result<bench::Plan> parse_plan(const BenchOptions& options, const engine::Options& base) {
  bench::Plan plan;
  plan.base = base;
  plan.methods.clear();
  for (const std::string& name : options.methods) {
    Result<engine::Method> m = engine::parse_method(name);
    if (!m) return std::unexpected(m.error());
    plan.methods.push_back(*m);
  }
  plan.masks.clear();
  for (const std::string& name : options.masks) {
    Result<lut::MaskMode> m = lut::parse_mask_mode(name);
    if (!m) return std::unexpected(m.error());
    plan.masks.push_back(*m);
  }
  plan.embree_rays.clear();
  for (const std::string& name : options.embree_rays) {
    Result<EmbreeRays> r = parse_embree_rays(name);
    if (!r) return std::unexpected(r.error());
    plan.embree_rays.push_back(*r);
  }
  plan.isas.clear();
  for (const std::string& name : options.isas) {
    Result<std::optional<Isa>> isa = parse_isa(name);
    if (!isa) return std::unexpected(isa.error());
    plan.isas.push_back(*isa);
  }
  for (const std::string& spec : options.lod) {
    LodCliOptions cli = options.lod_settings;
    cli.lod = spec;
    Result<std::optional<raster::LodOptions>> lod = parse_lod(cli);
    if (!lod) return std::unexpected(lod.error());
    if (*lod) plan.lods.push_back(**lod);
  }
  plan.samples = options.samples;
  plan.radii.clear();
  for (const std::string& text : options.radii) {
    Result<engine::Length> radius = parse_radius(text);
    if (!radius) return std::unexpected(radius.error());
    plan.radii.push_back({*radius, text});
  }
  plan.repeats = options.repeats;
  plan.stats = options.stats;
  return plan;
}

// Every row's AO as a PNG preview in `folder`, named by N, r, method, masks, isa and eps_1.
Result<void> write_row_png(const std::string& folder, const bench::Run& run, const MaskSet& masks,
                           const PixelReceivers& pixels, bool on_pixels) {
  AoImage image;
  image.width = pixels.width;
  image.height = pixels.height;
  image.ao.assign(static_cast<std::size_t>(pixels.width) * static_cast<std::size_t>(pixels.height), 1.0f);
  image.coverage.assign(image.ao.size(), 0.0f);
  for (std::size_t r = 0; r < pixels.receivers.size(); ++r) {
    const std::size_t at = on_pixels ? pixels.pixel[r] : r;  // bake receivers: one row
    image.ao[at] = masks.ao(r);
    image.coverage[at] = 1.0f;
  }
  std::string name = "/" + std::to_string(run.samples) + "-" + run.radius_text + "-" + run.method + "-" + run.masks;
  if (!run.isa.empty()) name += "-" + run.isa;
  if (run.method == "raster+lod") name += "-" + std::to_string(run.lod_eps1);
  return write_png(image, folder + name + ".png");
}

// Pixel receivers come from the scene as every command loads it; bake receivers from the
// scene as the bake reads it (a glTF's default scene, or the soup converted with an atlas).
Result<bench::Workload> open_workload(const BenchOptions& options, const bench::Plan& plan) {
  bench::Workload workload;
  workload.name = options.scene.scene;
  if (!plan.bake) {
    Result<Scene> scene = open_scene(options.scene);
    if (!scene) return std::unexpected(scene.error());
    workload.scene = std::move(*scene);
  } else {
    Result<bake::Document> document = bench::open_document(options.scene.scene, *plan.bake);
    if (!document) return std::unexpected(document.error());
    workload.document = std::move(*document);
    workload.scene = workload.document->scene();
  }
  Result<View> view = choose_view(options.camera, workload.scene);
  if (!view) return std::unexpected(view.error());
  workload.camera = view->camera;
  workload.width = view->width;
  workload.height = view->height;
  return workload;
}

// --json, --svg and --markdown.
Result<void> write_outputs(const BenchOptions& options, const bench::Report& results) {
  if (!options.json.empty()) {
    if (auto ok = write_bench_json(results, options.json); !ok) return ok;
  }
  if (!options.svg.empty()) {
    if (auto ok = write_bench_svg(results, options.svg); !ok) return ok;
  }
  if (!options.markdown.empty()) return write_bench_markdown(results, options.markdown);
  return {};
}

// The library's errors name its options; these are the flags that stand for them here.
const FlagOverrides kPlanFlags{{"method", "--methods"}, {"repeats", "--repeats"}};
const FlagOverrides kRunFlags{{"shard", "--shard"}};

int run_bench(const BenchOptions& options, const Invocation&) {
  Result<std::optional<engine::Shard>> shard = resolve_shard(options.shard);
  if (!shard) return report(shard.error());
  const bool on_pixels = options.receivers == "pixels";
  if (*shard && on_pixels) {
    return report(Error{"--shard: only with --receivers vertices or texels:SIZE (a bake's receivers, cut into chunks)"});
  }
  Result<engine::Options> base = make_options(options.scene, options.rays, options.method);
  if (!base) return report(base.error());
  print_thread_note(base->threads);
  Result<bench::Plan> parsed = parse_plan(options, *base);
  if (!parsed) return report(parsed.error(), kPlanFlags);
  if (!on_pixels) {
    // Checked before the scene is read.
    Result<bake::BakeOptions> bake = receivers_bake(options.receivers);
    if (!bake) return report(bake.error());
    parsed->bake = *bake;
  }
  parsed->shard = *shard;
  parsed->label = options.label.empty() ? options.scene.scene + " " + options.receivers : options.label;
  if (*shard) parsed->label += " shard " + std::to_string((*shard)->index) + "/" + std::to_string((*shard)->count);
  Result<bench::Plan> plan = bench::check_plan(std::move(*parsed));
  if (!plan) return report(plan.error(), kPlanFlags);

  Result<bench::Workload> opened = open_workload(options, *plan);
  if (!opened) return report(opened.error());
  bench::Workload& workload = *opened;

  Result<bench::Setup> setup = bench::prepare(*plan, workload);
  if (!setup) return report(setup.error());
  if (*shard) {
    std::printf("shard %zu/%zu: %zu of %zu receivers\n", (*shard)->index, (*shard)->count,
                setup->receivers.receivers.size(), setup->all_receivers);
  }
  if (on_pixels && setup->receivers.receivers.empty()) {
    return report(Error{options.scene.scene + ": the camera sees no triangle; try --eye/--target"});
  }
  if (auto ok = bench::check_receivers(*plan, workload, *setup); !ok) return report(ok.error(), kRunFlags);
  print_bench_header(setup->report);

  std::unique_ptr<ProgressBar> bar;
  bench::Events events;
  events.radius_ready = [](const engine::Engine& engine) { print_ray_notes(engine); };
  events.lod_built = [](const engine::LodLevels& lod) { std::printf("%s\n", describe_lod(lod).c_str()); };
  events.progress_started = [&bar](const std::string& label) {
    bar = std::make_unique<ProgressBar>(label);
    return bar->callback();
  };
  events.progress_finished = [&bar] { bar.reset(); };
  events.row = [&](const bench::Run& run, const MaskSet& masks) -> Result<void> {
    print_bench_row(run, options.stats);
    if (options.png_dir.empty()) return {};
    return write_row_png(options.png_dir, run, masks, setup->receivers, on_pixels);
  };
  Result<bench::Report> results = bench::run(*plan, workload, *setup, events);
  if (!results) return report(results.error(), kRunFlags);
  if (auto ok = write_outputs(options, *results); !ok) return report(ok.error());
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
  add_structure_options(*command, options->method);
  command->add_option("--receivers", options->receivers,
                      "Receivers: pixels (of the camera), vertices (of a vertex bake) or texels:SIZE[:SAMPLES] "
                      "(of a texture bake, SAMPLES per texel, default 1)")
      ->capture_default_str();
  command->add_option("--lod", options->lod,
                      "raster+lod rows (paper Sec. 4.3), a list of auto or eps_1 lengths (ascending: the smallest "
                      "eps_1 3^j serves the rest); off: none")
      ->delimiter(',')
      ->capture_default_str();
  add_lod_level_options(*command, options->lod_settings);
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
