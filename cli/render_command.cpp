// exao render: AO from a camera, to OpenEXR plus a PNG preview.

#include <chrono>
#include <cstdio>
#include <memory>

#include "cli/commands.h"
#include "cli/common_options.h"
#include "cli/lod_options.h"
#include "cli/progress_bar.h"
#include "io/image_io.h"
#include "core/pixel_receivers.h"
#include "engine/engine.h"

namespace exao::cli {
namespace {

struct RenderOptions {
  SceneOptions scene;
  RayOptions rays;
  CameraOptions camera;
  MethodOptions method;
  LodCliOptions lod;
  std::string output = "ao.exr";
  std::string png = "ao.png";
  bool counts = false;
  bool stats = false;
  ShardCliOptions shard;
};

// From blocked-ray counts (one per receiver): what a merge has, and what the masks give.
AoImage to_image(const PixelReceivers& pixels, std::span<const std::uint32_t> blocked, int samples, bool counts) {
  AoImage image;
  image.width = pixels.width;
  image.height = pixels.height;
  const std::size_t n = static_cast<std::size_t>(pixels.width) * static_cast<std::size_t>(pixels.height);
  image.ao.assign(n, 1.0f);
  image.coverage.assign(n, 0.0f);
  if (counts) image.blocked.assign(n, 0);
  for (std::size_t r = 0; r < pixels.receivers.size(); ++r) {
    image.ao[pixels.pixel[r]] = ao_from_blocked(static_cast<int>(blocked[r]), samples);
    image.coverage[pixels.pixel[r]] = 1.0f;
    if (counts) image.blocked[pixels.pixel[r]] = blocked[r];
  }
  return image;
}

// The engine's options from the flags, with the level of detail, checked for a camera's pixels.
Result<engine::Options> render_options(const RenderOptions& options) {
  Result<engine::Options> engine_options = make_options(options.scene, options.rays, options.method);
  if (!engine_options) return engine_options;
  Result<std::optional<raster::LodOptions>> lod = parse_lod(options.lod);
  if (!lod) return std::unexpected(lod.error());
  engine_options->lod = *lod;
  if (auto ok = engine::check_options(*engine_options); !ok) return std::unexpected(ok.error());
  if (auto ok = engine::check_serves(*engine_options, engine::Receivers::Pixels); !ok) return std::unexpected(ok.error());
  return engine_options;
}

// Every pixel receiver's blocked-ray count: from its mask, or with exao merge from the parts'
// counts (no rays are cast: engine::RunOptions::supplied_blocked). `stats` may be null.
// `seconds`: the run's time, the progress bar's life included, the counts from masks not.
Result<std::vector<std::uint32_t>> blocked_counts(const engine::Engine& engine, const PixelReceivers& pixels,
                                                  const Camera& camera, const Invocation& invocation, engine::Stats* stats,
                                                  double& seconds) {
  Result<MaskSet> masks;
  std::vector<std::uint32_t> blocked;
  const auto start = std::chrono::steady_clock::now();
  {
    ProgressBar bar("render");
    engine::RunOptions run;
    run.progress = bar.callback();
    run.stats = stats;
    if (invocation.merge) {
      run.supplied_blocked = invocation.merge->blocked;
      blocked.resize(pixels.receivers.size());
      engine::Outputs outputs;
      outputs.blocked = blocked;
      if (auto ok = engine.run(pixels.receivers, outputs, run); !ok) return std::unexpected(ok.error());
      masks = MaskSet();
    } else {
      masks = engine.pixel_masks(pixels, camera, run);
    }
  }
  seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (!masks) return std::unexpected(masks.error());
  if (!invocation.merge) {
    blocked.resize(masks->size());
    for (std::size_t r = 0; r < blocked.size(); ++r) blocked[r] = static_cast<std::uint32_t>(masks->blocked_count(r));
  }
  return blocked;
}

int run_render(const RenderOptions& options, const Invocation& invocation) {
  const std::string output = invocation.merge && !invocation.merge->output.empty() ? invocation.merge->output : options.output;
  if (auto ok = check_output(output, options.scene.scene); !ok) return report(ok.error());
  if (auto ok = check_output(options.png, options.scene.scene); !ok) return report(ok.error());
  Result<engine::Options> engine_options = render_options(options);
  if (!engine_options) return report(engine_options.error());
  Result<std::optional<engine::Shard>> shard = resolve_shard(options.shard);
  if (!shard) return report(shard.error());
  // Raster draws the whole image at once: it has no chunks of receivers to share out.
  if (*shard && engine_options->method == engine::Method::Raster) {
    return report(Error{"--shard: --method raster computes a camera's whole image at once; shard with bvh, brute or embree"});
  }

  Result<Scene> scene = open_scene(options.scene);
  if (!scene) return report(scene.error());
  Result<View> view = choose_view(options.camera, *scene);
  if (!view) return report(view.error());
  Result<engine::Engine> engine = engine::Engine::build(*scene, *engine_options, engine::Receivers::Pixels);
  if (!engine) return report(engine.error());
  print_option_notes(*engine);

  // The G-buffer counts in the frame's time; the levels of detail, built once per scene and
  // radius, do not: they are built before the clock starts, and said.
  const auto gbuffer_start = std::chrono::steady_clock::now();
  Result<PixelReceivers> pixels_result = engine->render_pixels(view->camera, view->width, view->height);
  const double gbuffer_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - gbuffer_start).count();
  if (!pixels_result) return report(pixels_result.error());
  const PixelReceivers& pixels = *pixels_result;
  Result<std::optional<engine::LodLevels>> levels = std::optional<engine::LodLevels>{};
  if (engine_options->lod) {
    ProgressBar bar("lod");
    levels = engine->prepare_lod(pixels, view->camera, bar.callback());
  }
  if (!levels) return report(levels.error());
  if (*levels) std::printf("%s\n", describe_lod(**levels).c_str());
  if (*shard) {
    const JobRecord record = make_record("render", invocation, {options.scene.scene}, output, pixels.receivers,
                                         engine->samples());
    return run_shard(record, *engine, pixels.receivers, **shard);
  }
  if (invocation.merge) {
    if (auto ok = check_merge_receivers(*invocation.merge, pixels.receivers); !ok) return report(ok.error());
  }

  engine::Stats stats;
  double run_seconds = 0.0;
  Result<std::vector<std::uint32_t>> counts =
      blocked_counts(*engine, pixels, view->camera, invocation, options.stats ? &stats : nullptr, run_seconds);
  if (!counts) return report(counts.error());
  const double seconds = gbuffer_seconds + run_seconds;
  const std::vector<std::uint32_t>& blocked = *counts;
  const AoImage image = to_image(pixels, blocked, engine->samples(), options.counts);
  if (auto ok = write_exr(image, output); !ok) return report(ok.error());
  if (!options.png.empty()) {
    if (auto ok = write_png(image, options.png); !ok) return report(ok.error());
  }
  const double mrays = static_cast<double>(pixels.receivers.size()) * engine->samples() / seconds * 1e-6;
  std::printf("%s: %zu triangles, %dx%d, %zu receivers, N=%d, r=%g, %s: %.3f s (%.1f Mrays/s) -> %s%s%s\n",
              options.scene.scene.c_str(), scene->triangle_count(), pixels.width, pixels.height,
              pixels.receivers.size(), engine->samples(), static_cast<double>(engine->radius()),
              *levels ? "raster+lod" : engine::method_name(engine->method()), seconds, mrays, output.c_str(),
              options.png.empty() ? "" : ", ", options.png.c_str());
  if (invocation.merge) std::printf("  AO from %s (the time above casts no rays)\n", invocation.merge->parts.c_str());
  if (options.stats) print_stats(stats, engine->options().isa);
  return 0;
}

}  // namespace

Command add_render_command(CLI::App& app) {
  auto options = std::make_shared<RenderOptions>();
  CLI::App* command = app.add_subcommand("render", "Ambient occlusion seen from a camera, to OpenEXR and PNG");
  add_scene_options(*command, options->scene);
  add_ray_options(*command, options->rays);
  add_camera_options(*command, options->camera);
  add_method_options(*command, options->method);
  add_lod_options(*command, options->lod);
  command->add_option("-o,--output", options->output, "OpenEXR output (Y = AO, A = coverage)")->capture_default_str();
  command->add_option("--png", options->png, "PNG preview (empty: none)")->capture_default_str();
  command->add_flag("--counts", options->counts, "Add a 'blocked' channel with the blocked-ray count");
  command->add_flag("--stats", options->stats, "Print work counters: per receiver (bvh), or the culling stages (raster, slower)");
  add_shard_options(*command, options->shard, false);
  return [options, command](const Invocation& invocation) { return command->parsed() ? run_render(*options, invocation) : -1; };
}

}  // namespace exao::cli
