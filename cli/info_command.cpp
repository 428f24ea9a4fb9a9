// exao info: what a scene holds, and a radius to start from.

#include <cstdio>
#include <memory>

#include "cli/commands.h"
#include "cli/common_options.h"
#include "engine/options.h"

namespace exao::cli {
namespace {

int run_info(const SceneOptions& options) {
  Result<Sidedness> sided = parse_sidedness(options.sided);
  if (!sided) return report(sided.error());
  Result<Scene> scene = open_scene(options);
  if (!scene) return report(scene.error());
  apply_sidedness(*scene, *sided);
  const Bounds bounds = scene->bounds();
  const std::size_t two = two_sided_count(*scene);
  std::printf("scene        %s\n", options.scene.c_str());
  std::printf("triangles    %zu (%zu one-sided, %zu two-sided)\n", scene->triangle_count(), scene->triangle_count() - two, two);
  std::printf("read         %zu (%zu zero-area and %zu non-finite skipped)\n", scene->report.triangles_read,
              scene->report.zero_area_skipped, scene->report.non_finite_skipped);
  std::printf("bounds       (%g, %g, %g) - (%g, %g, %g)\n", double(bounds.lo.x), double(bounds.lo.y), double(bounds.lo.z),
              double(bounds.hi.x), double(bounds.hi.y), double(bounds.hi.z));
  std::printf("diagonal     %g\n", double(bounds.diagonal()));
  std::printf("cameras      %zu\n", scene->cameras.size());
  for (std::size_t i = 0; i < scene->cameras.size(); ++i) {
    std::printf("  %zu: %s\n", i, scene->cameras[i].name.c_str());
  }
  const engine::Length radius = engine::kDefaultRadius;
  std::printf("radius       %g (the default: %g%% of the diagonal)\n", double(radius.resolve(bounds.diagonal())),
              double(radius.value));
  return 0;
}

}  // namespace

Command add_info_command(CLI::App& app) {
  auto options = std::make_shared<SceneOptions>();
  CLI::App* command = app.add_subcommand("info", "Triangles, bounds, sidedness and a suggested radius");
  add_scene_options(*command, *options);
  return [options, command](const Invocation&) { return command->parsed() ? run_info(*options) : -1; };
}

}  // namespace exao::cli
