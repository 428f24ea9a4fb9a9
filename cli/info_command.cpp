// exao info: what a scene holds, and a radius to start from.

#include <cstdio>
#include <memory>
#include <string>

#include "core/cutouts.h"

#include "cli/commands.h"
#include "cli/common_options.h"
#include "engine/options.h"

namespace exao::cli {
namespace {

// The alpha-tested materials (as loaded) and how many triangles cut out under the policy.
void print_cutouts(const Cutouts* applied, const Cutouts* loaded) {
  std::printf("cut-outs     %zu triangles alpha-tested%s\n", applied ? applied->tested_count() : 0,
              loaded && !applied ? " (cut-outs off, or only BLEND materials, opaque)" : "");
  if (!loaded) return;
  for (std::size_t m = 0; m < loaded->materials.size(); ++m) {
    const CutoutMaterial& material = loaded->materials[m];
    const CutoutMaterial* now = applied ? &applied->materials[m] : nullptr;
    const char* rule = !now || now->rule == AlphaRule::Opaque ? "opaque"
                       : now->rule == AlphaRule::Stochastic ? "stochastic"
                                                           : "cutoff";
    std::string texture = "no texture";
    if (material.texture >= 0) {
      const AlphaTexture& t = *loaded->textures[static_cast<std::size_t>(material.texture)];
      texture = std::to_string(t.width) + "x" + std::to_string(t.height) + " alpha texture";
    }
    std::printf("  %s: %s, alpha %g x %s, %s", material.name.c_str(), material.blend ? "BLEND" : "MASK",
                double(material.factor), texture.c_str(), rule);
    if (now && now->rule == AlphaRule::Cutoff) std::printf(" at %g", double(now->cutoff));
    std::printf("\n");
  }
}

int run_info(const SceneOptions& options) {
  Result<Sidedness> sided = parse_sidedness(options.sided);
  if (!sided) return report(sided.error());
  Result<Scene> scene = open_scene(options);
  if (!scene) return report(scene.error());
  apply_sidedness(*scene, *sided);
  Result<CutoutPolicy> policy = parse_cutout_policy(options);
  if (!policy) return report(policy.error());
  const std::shared_ptr<const Cutouts> cutouts = apply_cutout_policy(scene->cutouts, *policy);
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
  print_cutouts(cutouts.get(), scene->cutouts.get());
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
