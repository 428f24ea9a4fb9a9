// exao query: AO at arbitrary points, one value a line, in the order of the input.

#include <chrono>
#include <cstdio>
#include <memory>

#include "cli/backends.h"
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

int run_query(const QueryOptions& options) {
  const auto threads = thread_limit(options.rays.threads);
  if (auto ok = check_output(options.output, options.scene.scene); !ok) return report(ok.error());
  if (auto ok = check_output(options.output, options.points); !ok) return report(ok.error());
  Result<Method> method = parse_method(options.method.method);
  if (!method) return report(method.error());
  Result<BackendOptions> backend_options = make_backend_options(options.method);
  if (!backend_options) return report(backend_options.error());
  Result<std::vector<Receiver>> receivers = load_receivers(options.points);
  if (!receivers) return report(receivers.error());
  Result<Scene> scene = open_scene(options.scene);
  if (!scene) return report(scene.error());
  Result<ShadowRays> rays = make_rays(options.rays, *scene);
  if (!rays) return report(rays.error());
  const Method methods[] = {*method};
  Result<Backends> backends = Backends::prepare(*scene, methods, *backend_options);
  if (!backends) return report(backends.error());
  std::optional<lut::MaskEngine> engine;
  if (*method != Method::Embree) {
    Result<lut::MaskEngine> built = backends->engine(*rays, backend_options->masks);
    if (!built) return report(built.error());
    engine = std::move(*built);
  }
  const auto start = std::chrono::steady_clock::now();
  MaskSet masks;
  BackendStats stats;
  {
    ProgressBar bar("query");
    masks = backends->run(*method, *rays, engine ? &*engine : nullptr, *receivers, bar.callback(),
                          options.stats ? &stats : nullptr);
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::vector<float> ao(masks.size());
  for (std::size_t i = 0; i < masks.size(); ++i) ao[i] = masks.ao(i);
  if (auto ok = save_values(ao, options.output); !ok) return report(ok.error());
  std::printf("%s: %zu receivers, N=%d, r=%g, %s: %.3f s (%.1f Mrays/s) -> %s\n", options.points.c_str(),
              receivers->size(), rays->count(), static_cast<double>(rays->radius), method_name(*method), seconds,
              static_cast<double>(receivers->size()) * rays->count() / seconds * 1e-6, options.output.c_str());
  if (options.stats) print_stats(stats);
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
  command->add_flag("--stats", options->stats, "Print work counters per receiver (bvh)");
  return [options, command]() { return command->parsed() ? run_query(*options) : -1; };
}

}  // namespace exao::cli
