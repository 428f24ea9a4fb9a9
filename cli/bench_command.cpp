// exao bench: every method on the same receivers and rays, timed side by side, compared with
// Embree ray for ray. A table on stdout, optionally JSON and an SVG bar chart.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>
#include <sstream>

#include <tbb/global_control.h>
#include <tbb/info.h>

#include "cli/backends.h"
#include "cli/bench_report.h"
#include "cli/commands.h"
#include "cli/common_options.h"
#include "cli/progress_bar.h"
#include "core/atomic_write.h"
#include "core/pixel_receivers.h"

namespace exao::cli {
namespace {

struct BenchOptions {
  SceneOptions scene;
  RayOptions rays;
  CameraOptions camera;
  MethodOptions method;
  std::vector<int> samples{128, 1024};
  std::vector<std::string> radii{"1%", "5%"};
  std::vector<std::string> methods{"embree", "bvh"};
  std::vector<std::string> masks{"lut", "exact"};
  std::vector<std::string> embree_rays{"packet16"};
  int repeats = 1;
  std::string json;
  std::string svg;
  bool stats = false;
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

int run_bench(const BenchOptions& options) {
  const auto threads = thread_limit(options.rays.threads);
  if (!threads) return report(threads.error());
  std::vector<Method> methods;
  for (const std::string& name : options.methods) {
    Result<Method> m = parse_method(name);
    if (!m) return report(m.error());
    methods.push_back(*m);
  }
  std::vector<lut::MaskMode> modes;
  for (const std::string& name : options.masks) {
    Result<lut::MaskMode> m = lut::parse_mask_mode(name);
    if (!m) return report(m.error());
    modes.push_back(*m);
  }
  std::vector<EmbreeRays> embree_modes;
  for (const std::string& name : options.embree_rays) {
    Result<EmbreeRays> r = parse_embree_rays(name);
    if (!r) return report(r.error());
    embree_modes.push_back(*r);
  }
  if (embree_modes.empty()) return report(Error{"--embree-rays: give at least one mode"});
  for (const int n : options.samples) {
    if (auto ok = check_sample_count(n); !ok) return report(ok.error());
  }
  if (options.repeats < 1) return report(Error{"--repeats: must be at least 1"});
  Result<BackendOptions> backend_options = make_backend_options(options.method);
  if (!backend_options) return report(backend_options.error());

  Result<Scene> scene = open_scene(options.scene);
  if (!scene) return report(scene.error());
  Result<Camera> camera = choose_camera(options.camera, *scene);
  if (!camera) return report(camera.error());
  Result<int> height = image_height(options.camera, *camera);
  if (!height) return report(height.error());
  Result<Backends> backends = Backends::prepare(*scene, methods, *backend_options);
  if (!backends) return report(backends.error());
  const PixelReceivers pixels = pixel_receivers(backends->embree(), *scene, *camera, options.camera.width, *height);
  if (pixels.receivers.empty()) return report(Error{options.scene.scene + ": the camera sees no triangle; try --eye/--target"});

  BenchReport report_data;
  report_data.scene = options.scene.scene;
  report_data.triangles = scene->triangle_count();
  report_data.receivers = pixels.receivers.size();
  report_data.threads = options.rays.threads > 0 ? options.rays.threads : tbb::info::default_concurrency();
  report_data.width = pixels.width;
  report_data.height = pixels.height;
  print_bench_header(report_data);

  for (const int n : options.samples) {
    for (const std::string& radius_text : options.radii) {
      RayOptions ray_options = options.rays;
      ray_options.samples = n;
      ray_options.radius = radius_text;
      Result<ShadowRays> rays = make_rays(ray_options, *scene);
      if (!rays) return report(rays.error());
      std::vector<std::unique_ptr<lut::MaskEngine>> engines(2);
      for (const lut::MaskMode mode : modes) {
        Result<lut::MaskEngine> engine = backends->engine(*rays, mode);
        if (!engine) return report(engine.error());
        engines[static_cast<int>(mode)] = std::make_unique<lut::MaskEngine>(std::move(*engine));
      }
      // The configurations of this (N, r): Embree first, the reference for every comparison.
      struct Config { Method method; lut::MaskMode mode; EmbreeRays rays; };
      std::vector<Config> configs;
      for (const EmbreeRays r : embree_modes) configs.push_back({Method::Embree, lut::MaskMode::Exact, r});
      for (const Method m : methods) {
        if (m == Method::Embree) continue;
        for (const lut::MaskMode mode : modes) configs.push_back({m, mode, EmbreeRays::Single});
      }
      std::vector<BenchRun> runs(configs.size());
      std::vector<MaskSet> results(configs.size());
      // Interleaved repeats: drift of the machine hits every method alike; the fastest counts.
      for (int repeat = 0; repeat < options.repeats; ++repeat) {
        for (std::size_t c = 0; c < configs.size(); ++c) {
          const Config& config = configs[c];
          const lut::MaskEngine* engine = engines[static_cast<int>(config.mode)].get();
          BackendStats stats;
          ProgressBar bar(std::string("bench ") + method_name(config.method));
          const auto start = std::chrono::steady_clock::now();
          MaskSet masks = config.method == Method::Raster
                              ? backends->run_raster(*engine, pixels, *camera, bar.callback(), options.stats ? &stats : nullptr)
                              : backends->run(config.method, *rays, engine, pixels.receivers, bar.callback(),
                                              options.stats ? &stats : nullptr, config.rays);
          const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
          bar.finish();
          BenchRun& run = runs[c];
          if (repeat == 0 || seconds < run.seconds) run.seconds = seconds;
          if (repeat == 0) {
            run.samples = n;
            run.radius = rays->radius;
            run.radius_text = radius_text;
            run.method = method_name(config.method);
            run.masks = config.method == Method::Embree ? embree_rays_name(config.rays) : lut::mask_mode_name(config.mode);
            run.stats = stats;
            results[c] = std::move(masks);
          }
        }
      }
      for (std::size_t c = 0; c < configs.size(); ++c) {
        BenchRun& run = runs[c];
        run.mrays_per_s = static_cast<double>(pixels.receivers.size()) * n / run.seconds * 1e-6;
        run.speedup_vs_embree = runs[0].seconds / run.seconds;
        compare(results[0], results[c], run);
        print_bench_row(run, options.stats);
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
  command->add_option("--methods", options->methods, "Methods to time besides embree: brute, bvh, raster (raster on Embree's pixel receivers)")->delimiter(',')->capture_default_str();
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
  command->add_option("--repeats", options->repeats, "Interleaved repeats; the fastest time counts")->capture_default_str();
  command->add_option("--json", options->json, "Write the results as JSON");
  command->add_option("--svg", options->svg, "Write a bar chart of Mrays/s as SVG");
  command->add_flag("--stats", options->stats, "Add BVH work counters per receiver");
  return [options, command]() { return command->parsed() ? run_bench(*options) : -1; };
}

}  // namespace exao::cli
