// exao query: AO at arbitrary points, one value a line, in the order of the input, by the
// library engine that the public API (include/exao/exao.hpp) also wraps.

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>

#include "cli/commands.h"
#include "cli/common_options.h"
#include "cli/progress_bar.h"
#include "io/receiver_io.h"
#include "engine/engine.h"

namespace exao::cli {
namespace {

struct QueryOptions {
  SceneOptions scene;
  RayOptions rays;
  MethodOptions method;
  std::string points;
  std::string output = "ao.txt";
  bool stats = false;
  ShardCliOptions shard;
};

// Where the BVH's bytes go, per triangle (issue 21: memory per triangle).
void print_bvh_bytes(const bvh::Bvh& tree) {
  const bvh::BvhBytes bytes = bvh::memory_bytes(tree);
  const double n = static_cast<double>(tree.triangle_count());
  const auto per = [&](std::size_t b) { return static_cast<double>(b) / n; };
  const double leaves = static_cast<double>(std::max<std::size_t>(1, tree.leaf_count));
  std::printf("bvh memory: %.1f bytes a triangle: nodes %.1f (%zu), leaves %.1f (%zu, %.2f triangles a leaf), "
              "indices %.1f\n",
              per(bytes.total()), per(bytes.nodes), tree.nodes.size(), per(bytes.leaves), tree.leaf_count, n / leaves,
              per(bytes.indices));
  std::size_t by_size[9] = {};  // [0]: internal children, not printed
  for (const bvh::Node& node : tree.nodes) {
    for (int k = 0; k < node.child_count; ++k) ++by_size[node.leaf_size[k]];
  }
  std::printf("leaves by size:");
  for (int size = 1; size <= 8; ++size) std::printf(" %d: %.1f%%", size, 100.0 * static_cast<double>(by_size[size]) / leaves);
  std::printf("\n");
}

int run_query(const QueryOptions& options, const Invocation& invocation) {
  const std::string output = invocation.merge && !invocation.merge->output.empty() ? invocation.merge->output : options.output;
  if (auto ok = check_output(output, options.scene.scene); !ok) return report(ok.error());
  if (auto ok = check_output(output, options.points); !ok) return report(ok.error());
  Result<engine::Options> engine_options = make_options(options.scene, options.rays, options.method);
  if (!engine_options) return report(engine_options.error());
  if (auto ok = engine::check_serves(*engine_options, engine::Receivers::Points); !ok) return report(ok.error());
  Result<std::optional<engine::Shard>> shard = resolve_shard(options.shard);
  if (!shard) return report(shard.error());
  Result<std::vector<Receiver>> receivers = load_receivers(options.points);
  if (!receivers) return report(receivers.error());
  if (invocation.merge) {
    if (auto ok = check_merge_receivers(*invocation.merge, *receivers); !ok) return report(ok.error());
  }
  const auto load_start = std::chrono::steady_clock::now();
  Result<Scene> scene = open_scene(options.scene);
  if (!scene) return report(scene.error());
  const auto build_start = std::chrono::steady_clock::now();
  const std::size_t triangles = scene->triangle_count();
  // The engine takes the scene: its arrays are freed as the backends are built (the BVH keeps
  // its own copy of every triangle, Embree reads the vertices in place).
  Result<engine::Engine> engine = [&] {
    ProgressBar bar("build");
    return engine::Engine::build(std::move(*scene), *engine_options, engine::Receivers::Points, bar.callback());
  }();
  if (!engine) return report(engine.error());
  const auto built = std::chrono::steady_clock::now();
  const double load_seconds = std::chrono::duration<double>(build_start - load_start).count();
  const double build_seconds = std::chrono::duration<double>(built - build_start).count();
  print_option_notes(*engine);
  if (*shard) {
    const JobRecord record = make_record("query", invocation, {options.scene.scene, options.points}, output, *receivers,
                                         engine->samples());
    return run_shard(record, *engine, *receivers, **shard);
  }

  engine::Stats stats;
  Result<std::vector<float>> ao;
  const auto start = std::chrono::steady_clock::now();
  {
    ProgressBar bar("query");
    engine::RunOptions run;
    run.progress = bar.callback();
    if (options.stats) run.stats = &stats;
    if (invocation.merge) run.supplied_blocked = invocation.merge->blocked;
    ao = engine->ao(*receivers, run);
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (!ao) return report(Error{options.points + ": " + ao.error().message});
  if (auto ok = save_values(*ao, output); !ok) return report(ok.error());
  std::printf("%s: %zu triangles, loaded in %.3f s, prepared in %.3f s\n", options.scene.scene.c_str(), triangles,
              load_seconds, build_seconds);
  std::printf("%s: %zu receivers, N=%d, r=%g, %s: %.3f s (%.1f Mrays/s) -> %s\n", options.points.c_str(),
              receivers->size(), engine->samples(), static_cast<double>(engine->radius()),
              engine::method_name(engine->method()), seconds,
              static_cast<double>(receivers->size()) * engine->samples() / seconds * 1e-6, output.c_str());
  if (invocation.merge) std::printf("  AO from %s (the time above casts no rays)\n", invocation.merge->parts.c_str());
  if (options.stats) {
    print_stats(stats, engine->options().isa);
    if (const bvh::Bvh* tree = engine->geometry().bvh()) print_bvh_bytes(*tree);
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
  add_shard_options(*command, options->shard, false);
  return [options, command](const Invocation& invocation) { return command->parsed() ? run_query(*options, invocation) : -1; };
}

}  // namespace exao::cli
