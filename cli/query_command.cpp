// exao query: AO at arbitrary points, one value a line, in the order of the input. A client of
// the public API (include/exao/exao.hpp), exactly as a renderer would be.

#include <chrono>
#include <cstdio>
#include <memory>

#include <exao/exao.hpp>

#include "cli/commands.h"
#include "cli/common_options.h"
#include "cli/progress_bar.h"
#include "core/receiver_io.h"

namespace exao::cli {
namespace {

struct QueryOptions {
  SceneOptions scene;
  RayOptions rays;
  MethodOptions method;
  std::string points;
  std::string output = "ao.txt";
  bool stats = false;
};

Result<api::Options> api_options(const QueryOptions& options, const api::SceneData& scene) {
  Bounds bounds;
  for (std::size_t i = 0; i + 2 < scene.positions.size(); i += 3) {
    bounds.extend({scene.positions[i], scene.positions[i + 1], scene.positions[i + 2]});
  }
  Result<float> radius = parse_radius(options.rays.radius, bounds.diagonal());
  if (!radius) return std::unexpected(radius.error());
  if (auto ok = check_radius(*radius, bounds.diagonal(), options.rays.offset.value_or(kDefaultOffsetFraction * bounds.diagonal())); !ok) {
    return std::unexpected(ok.error());
  }
  api::Options out;
  out.radius = *radius;
  out.samples = options.rays.samples;
  if (auto ok = check_sample_count(out.samples); !ok) return std::unexpected(ok.error());
  Result<Falloff> falloff = parse_falloff(options.rays.falloff);
  if (!falloff) return std::unexpected(falloff.error());
  out.falloff = static_cast<api::Falloff>(static_cast<int>(*falloff));
  out.origin_offset = options.rays.offset;
  if (auto ok = check_threads(options.rays.threads); !ok) return std::unexpected(ok.error());
  out.threads = options.rays.threads;
  out.sidedness = options.scene.sided == "one" ? api::Sidedness::One
                  : options.scene.sided == "two" ? api::Sidedness::Two
                                                 : api::Sidedness::Auto;
  Result<Method> method = parse_method(options.method.method);
  if (!method) return std::unexpected(method.error());
  out.backend = *method == Method::Embree ? api::Backend::Embree : *method == Method::Brute ? api::Backend::Brute : api::Backend::Bvh;
  Result<lut::MaskMode> masks = lut::parse_mask_mode(options.method.masks);
  if (!masks) return std::unexpected(masks.error());
  out.mask_mode = *masks == lut::MaskMode::Exact ? api::MaskMode::Exact : api::MaskMode::Lut;
  Result<EmbreeRays> embree_rays = parse_embree_rays(options.method.embree_rays);
  if (!embree_rays) return std::unexpected(embree_rays.error());
  out.embree_rays = static_cast<api::EmbreeRays>(static_cast<int>(*embree_rays));
  out.table_resolution = options.method.table_resolution;
  out.bvh_branching = options.method.branching;
  return out;
}

int run_query(const QueryOptions& options) {
  if (auto ok = check_output(options.output, options.scene.scene); !ok) return report(ok.error());
  if (auto ok = check_output(options.output, options.points); !ok) return report(ok.error());
  Result<std::vector<Receiver>> receivers = load_receivers(options.points);
  if (!receivers) return report(receivers.error());
  api::Result<api::SceneData> scene = api::load_scene(options.scene.scene);
  if (!scene) return report(Error{scene.error().message});
  for (const std::string& note : scene->notes) std::fprintf(stderr, "exao: %s: %s\n", options.scene.scene.c_str(), note.c_str());
  Result<api::Options> engine_options = api_options(options, *scene);
  if (!engine_options) return report(engine_options.error());
  api::Result<api::Engine> engine = api::Engine::build(scene->mesh(), *engine_options);
  if (!engine) return report(Error{engine.error().message});

  std::vector<api::Receiver> points(receivers->size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Receiver& r = (*receivers)[i];
    points[i] = {{r.position.x, r.position.y, r.position.z}, {r.normal.x, r.normal.y, r.normal.z}, r.key};
  }
  std::vector<float> ao(points.size());
  api::WorkStats stats;
  const auto start = std::chrono::steady_clock::now();
  {
    ProgressBar bar("query");
    api::BatchOptions batch;
    batch.progress = bar.callback();
    if (options.stats) batch.stats = &stats;
    if (api::Status status = engine->ao(points, ao, batch); !status.ok()) return report(Error{options.points + ": " + status.error().message});
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (auto ok = save_values(ao, options.output); !ok) return report(ok.error());
  const api::EngineInfo& info = engine->info();
  std::printf("%s: %zu receivers, N=%d, r=%g, %s: %.3f s (%.1f Mrays/s) -> %s\n", options.points.c_str(),
              points.size(), info.samples, static_cast<double>(info.radius), options.method.method.c_str(), seconds,
              static_cast<double>(points.size()) * info.samples / seconds * 1e-6, options.output.c_str());
  if (options.stats) {
    BackendStats backend_stats;
    backend_stats.traversal = {stats.receivers, stats.nodes_visited, stats.triangles_tested, stats.triangles_blocking};
    print_stats(backend_stats);
  }
  return 0;
}

}  // namespace

Command add_query_command(CLI::App& app) {
  auto options = std::make_shared<QueryOptions>();
  CLI::App* command = app.add_subcommand("query", "AO at arbitrary points (x y z nx ny nz [key] per line, or a PLY with normals)");
  add_scene_options(*command, options->scene);
  add_ray_options(*command, options->rays);
  add_method_options(*command, options->method);
  command->add_option("--points", options->points, "Receivers: a text file (x y z nx ny nz [key] a line) or a PLY with normals")
      ->required();
  command->add_option("-o,--output", options->output, "One AO value a line, in input order")->capture_default_str();
  command->add_flag("--stats", options->stats, "Print work counters: per receiver (bvh), or the culling stages (raster, slower)");
  return [options, command]() { return command->parsed() ? run_query(*options) : -1; };
}

}  // namespace exao::cli
