// exao render: AO from a camera, to OpenEXR plus a PNG preview.

#include <chrono>
#include <cstdio>
#include <memory>

#include "cli/commands.h"
#include "cli/common_options.h"
#include "cli/progress_bar.h"
#include "core/image_io.h"
#include "core/pixel_receivers.h"
#include "engine/engine.h"

namespace exao::cli {
namespace {

struct RenderOptions {
  SceneOptions scene;
  RayOptions rays;
  CameraOptions camera;
  MethodOptions method;
  std::string output = "ao.exr";
  std::string png = "ao.png";
  bool counts = false;
  bool stats = false;
};

AoImage to_image(const PixelReceivers& pixels, const MaskSet& masks, bool counts) {
  AoImage image;
  image.width = pixels.width;
  image.height = pixels.height;
  const std::size_t n = static_cast<std::size_t>(pixels.width) * static_cast<std::size_t>(pixels.height);
  image.ao.assign(n, 1.0f);
  image.coverage.assign(n, 0.0f);
  if (counts) image.blocked.assign(n, 0);
  for (std::size_t r = 0; r < pixels.receivers.size(); ++r) {
    image.ao[pixels.pixel[r]] = masks.ao(r);
    image.coverage[pixels.pixel[r]] = 1.0f;
    if (counts) image.blocked[pixels.pixel[r]] = static_cast<std::uint32_t>(masks.blocked_count(r));
  }
  return image;
}

int run_render(const RenderOptions& options) {
  if (auto ok = check_output(options.output, options.scene.scene); !ok) return report(ok.error());
  if (auto ok = check_output(options.png, options.scene.scene); !ok) return report(ok.error());
  Result<engine::Options> engine_options = make_options(options.scene, options.rays, options.method);
  if (!engine_options) return report(engine_options.error());
  if (auto ok = engine::check_serves(*engine_options, engine::Receivers::Pixels); !ok) return report(ok.error());

  Result<Scene> scene = open_scene(options.scene);
  if (!scene) return report(scene.error());
  Result<View> view = choose_view(options.camera, *scene);
  if (!view) return report(view.error());
  Result<engine::Engine> engine = engine::Engine::build(*scene, *engine_options, engine::Receivers::Pixels);
  if (!engine) return report(engine.error());
  print_option_notes(*engine);

  engine::Stats stats;
  Result<engine::PixelResult> result;
  const auto start = std::chrono::steady_clock::now();
  {
    ProgressBar bar("render");
    engine::RunOptions run;
    run.progress = bar.callback();
    if (options.stats) run.stats = &stats;
    result = engine->render(view->camera, view->width, view->height, run);
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (!result) return report(result.error());

  const PixelReceivers& pixels = result->pixels;
  const AoImage image = to_image(pixels, result->masks, options.counts);
  if (auto ok = write_exr(image, options.output); !ok) return report(ok.error());
  if (!options.png.empty()) {
    if (auto ok = write_png(image, options.png); !ok) return report(ok.error());
  }
  const double mrays = static_cast<double>(pixels.receivers.size()) * engine->samples() / seconds * 1e-6;
  std::printf("%s: %zu triangles, %dx%d, %zu receivers, N=%d, r=%g, %s: %.3f s (%.1f Mrays/s) -> %s%s%s\n",
              options.scene.scene.c_str(), scene->triangle_count(), pixels.width, pixels.height,
              pixels.receivers.size(), engine->samples(), static_cast<double>(engine->radius()),
              engine::method_name(engine->method()), seconds, mrays, options.output.c_str(),
              options.png.empty() ? "" : ", ", options.png.c_str());
  if (options.stats) print_stats(stats);
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
  command->add_option("-o,--output", options->output, "OpenEXR output (Y = AO, A = coverage)")->capture_default_str();
  command->add_option("--png", options->png, "PNG preview (empty: none)")->capture_default_str();
  command->add_flag("--counts", options->counts, "Add a 'blocked' channel with the blocked-ray count");
  command->add_flag("--stats", options->stats, "Print work counters: per receiver (bvh), or the culling stages (raster, slower)");
  return [options, command]() { return command->parsed() ? run_render(*options) : -1; };
}

}  // namespace exao::cli
