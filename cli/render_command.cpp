// exao render: AO from a camera, to OpenEXR plus a PNG preview.

#include <chrono>
#include <cstdio>
#include <memory>

#include <tbb/global_control.h>

#include "cli/commands.h"
#include "cli/common_options.h"
#include "cli/progress_bar.h"
#include "core/embree_reference.h"
#include "core/image_io.h"
#include "core/pixel_receivers.h"

namespace exao::cli {
namespace {

struct RenderOptions {
  SceneOptions scene;
  RayOptions rays;
  CameraOptions camera;
  std::string output = "ao.exr";
  std::string png = "ao.png";
  std::string method = "embree";
  std::string embree_rays = embree_rays_name(EmbreeOptions{}.rays);
  bool counts = false;
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
  std::unique_ptr<tbb::global_control> threads;
  if (options.rays.threads > 0) {
    threads = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, options.rays.threads);
  }
  if (auto ok = check_output(options.output, options.scene.scene); !ok) return report(ok.error());
  if (auto ok = check_output(options.png, options.scene.scene); !ok) return report(ok.error());
  Result<EmbreeRays> embree_rays = parse_embree_rays(options.embree_rays);
  if (!embree_rays) return report(embree_rays.error());

  Result<Scene> scene = open_scene(options.scene);
  if (!scene) return report(scene.error());
  Result<ShadowRays> rays = make_rays(options.rays, *scene);
  if (!rays) return report(rays.error());
  Result<Camera> camera = choose_camera(options.camera, *scene);
  if (!camera) return report(camera.error());
  Result<int> height = image_height(options.camera, *camera);
  if (!height) return report(height.error());
  Result<EmbreeScene> embree = EmbreeScene::build(*scene);
  if (!embree) return report(embree.error());

  const PixelReceivers pixels = pixel_receivers(*embree, *scene, *camera, options.camera.width, *height);
  const auto start = std::chrono::steady_clock::now();
  MaskSet masks;
  {
    ProgressBar bar("render");
    EmbreeOptions embree_options;
    embree_options.rays = *embree_rays;
    masks = embree->occlusion(*rays, pixels.receivers, embree_options, bar.callback());
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  const AoImage image = to_image(pixels, masks, options.counts);
  if (auto ok = write_exr(image, options.output); !ok) return report(ok.error());
  if (!options.png.empty()) {
    if (auto ok = write_png(image, options.png); !ok) return report(ok.error());
  }
  const double mrays = static_cast<double>(pixels.receivers.size()) * rays->count() / seconds * 1e-6;
  std::printf("%s: %zu triangles, %dx%d, %zu receivers, N=%d, r=%g, %s: %.3f s (%.1f Mrays/s) -> %s%s%s\n",
              options.scene.scene.c_str(), scene->triangle_count(), pixels.width, pixels.height,
              pixels.receivers.size(), rays->count(), static_cast<double>(rays->radius), options.method.c_str(),
              seconds, mrays, options.output.c_str(), options.png.empty() ? "" : ", ", options.png.c_str());
  return 0;
}

}  // namespace

Command add_render_command(CLI::App& app) {
  auto options = std::make_shared<RenderOptions>();
  CLI::App* command = app.add_subcommand("render", "Ambient occlusion seen from a camera, to OpenEXR and PNG");
  add_scene_options(*command, options->scene);
  add_ray_options(*command, options->rays);
  add_camera_options(*command, options->camera);
  command->add_option("-o,--output", options->output, "OpenEXR output (Y = AO, A = coverage)")->capture_default_str();
  command->add_option("--png", options->png, "PNG preview (empty: none)")->capture_default_str();
  command->add_option("--method", options->method, "embree")->check(CLI::IsMember({"embree"}))->capture_default_str();
  command->add_option("--embree-rays", options->embree_rays, "single, packet4, packet8 or packet16")->capture_default_str();
  command->add_flag("--counts", options->counts, "Add a 'blocked' channel with the blocked-ray count");
  return [options, command]() { return command->parsed() ? run_render(*options) : -1; };
}

}  // namespace exao::cli
