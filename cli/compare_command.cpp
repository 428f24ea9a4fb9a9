// exao compare: the screen-space AO methods of the seeds (ssao/) against exao's exact AO on the
// same G-buffer pixels: error statistics, times, pictures, JSON and a Markdown table; with
// --stereo, each method's inconsistency between the eyes (seed 003). A thin layer: the methods,
// the loop and the measurements are in ssao/ (ssao/comparison.h), the exact AO is the bvh method
// of the library engine (engine/); what it writes and prints is cli/compare_report.h's.

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>
#include <optional>
#include <string_view>
#include <utility>

#include <tbb/global_control.h>

#include "cli/commands.h"
#include "cli/common_options.h"
#include "cli/compare_report.h"
#include "cli/option_flags.h"
#include "cli/progress_bar.h"
#include "core/cutouts.h"
#include "engine/engine.h"
#include "ssao/compare.h"
#include "ssao/comparison.h"
#include "ssao/grazing_box.h"

namespace exao::cli {
namespace {

// The library names its options; the command's users know them by their flags.
Error as_flag_error(const Error& error) {
  static constexpr std::pair<const char*, const char*> kFlags[] = {
      {"methods:", "--methods:"},         {"directions:", "--directions:"}, {"steps:", "--steps:"},
      {"bias:", "--bias:"},               {"cosine:", "--cosine:"},         {"thickness:", "--thickness:"},   {"blur:", "--blur:"},
      {"stochastic depth samples:", "--sd-samples:"}, {"stochastic depth alpha:", "--sd-alpha:"},
      {"key cell:", "--key-cell:"},       {"radius:", "--radius:"},
      {"secondary view angle:", "--mv-angle:"}, {"stereo eye distance:", "--stereo:"},
  };
  for (const auto& [name, flag] : kFlags) {
    if (error.message.starts_with(name)) return Error{flag + error.message.substr(std::string_view(name).size())};
  }
  return error;
}

// The flags' own syntax, checked before any scene is read: the methods, --stereo, --angles,
// --key, --key-cell and the output folder.
Result<std::vector<ssao::Method>> check_flags(const CompareCommandOptions& o) {
  Result<std::vector<ssao::Method>> methods = ssao::parse_methods(o.methods);
  if (!methods) return std::unexpected(as_flag_error(methods.error()));
  if (o.stereo && !(std::isfinite(*o.stereo) && *o.stereo > 0.0)) return fail("--stereo: the eye distance must be greater than 0");
  if (o.angles != "view" && o.angles != "tangent") return fail("--angles: must be view or tangent, got '" + o.angles + "'");
  if (o.key != "pixel" && o.key != "world") return fail("--key: must be pixel or world, got '" + o.key + "'");
  if (!(std::isfinite(o.key_cell) && o.key_cell > 0.0)) return fail("--key-cell: must be greater than 0");
  if (auto ok = check_output(o.output, o.scene.scene); !ok) return std::unexpected(ok.error());
  return methods;
}

// The library's options of the comparison from the flags and the exact AO's rays, checked.
Result<ssao::CompareOptions> compare_options(const CompareCommandOptions& o, std::vector<ssao::Method> methods,
                                             const ShadowRays& rays) {
  ssao::CompareOptions options;
  options.methods = std::move(methods);
  options.settings.radius = rays.radius;
  options.settings.falloff = rays.pattern.falloff;
  options.settings.blur_radius = o.blur;
  options.hbao.directions = options.hbao_plus.directions = o.directions;
  options.hbao.steps = options.hbao_plus.steps = o.steps;
  options.hbao.bias = options.hbao_plus.bias = o.bias;
  options.hbao.cosine = o.cosine;
  options.hbao.angles = o.angles == "tangent" ? ssao::Angles::Tangent : ssao::Angles::ViewPlane;
  options.vao.thickness = o.thickness;
  options.stochastic.samples = o.sd_samples;
  options.stochastic.alpha = o.sd_alpha;
  if (o.key == "world") options.world_key_cell = static_cast<float>(o.key_cell * rays.radius);
  options.multiview.angle_degrees = o.mv_angle;
  options.keep_front_half = !o.compress_whole_list;
  // Stereo HBAO+'s other eye: --stereo's, or a tenth of the radius to the right.
  options.stereo_ipd = o.stereo ? *o.stereo : 0.1 * static_cast<double>(rays.radius);
  if (auto ok = ssao::check(options); !ok) return std::unexpected(as_flag_error(ok.error()));
  return options;
}

// The scene as the comparison sees it: seed 000's Fig. 3 case is a scene of the comparison's own
// (ssao/grazing_box.h); the G-buffer sees the sidedness and cut-outs the exact AO uses.
Result<Scene> compare_scene_of(const CompareCommandOptions& o, const engine::Options& engine_options) {
  Result<Scene> scene = o.scene.scene == ssao::kGrazingBoxName ? Result<Scene>(ssao::make_grazing_box()) : open_scene(o.scene);
  if (!scene) return scene;
  apply_sidedness(*scene, engine_options.sidedness);
  scene->cutouts = apply_cutout_policy(scene->cutouts, engine_options.cutouts);  // the A-buffer reads them too
  return scene;
}

int run_compare(const CompareCommandOptions& o) {
  Result<std::vector<ssao::Method>> methods = check_flags(o);
  if (!methods) return report(methods.error());
  MethodOptions method_options;
  method_options.method = engine::method_name(engine::Method::Bvh);
  method_options.masks = o.masks;
  Result<engine::Options> engine_options = make_options(o.scene, o.rays, method_options);
  if (!engine_options) return report(engine_options.error());
  // The screen-space methods run on TBB outside the engine's arena: the same thread limit.
  std::optional<tbb::global_control> threads;
  if (engine_options->threads > 0) {
    threads.emplace(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(engine_options->threads));
  }
  Result<Scene> scene = compare_scene_of(o, *engine_options);
  if (!scene) return report(scene.error());
  Result<engine::Engine> engine = engine::Engine::build(*scene, *engine_options, engine::Receivers::Points);
  if (!engine) return report(engine.error());
  print_option_notes(*engine);
  const ShadowRays& rays = engine->rays();
  Result<Camera> camera = choose_camera(o.camera, *scene);
  if (!camera) return report(camera.error());
  Result<int> height = image_height(o.camera, *camera);
  if (!height) return report(height.error());
  Result<ssao::CompareOptions> options = compare_options(o, std::move(*methods), rays);
  if (!options) return report(options.error());

  std::error_code ec;
  std::filesystem::create_directories(o.output, ec);
  if (ec || !std::filesystem::is_directory(o.output)) return report(Error{o.output + ": cannot create the output folder"});

  std::optional<Error> exact_error;
  const ssao::ExactAo exact = [&](std::span<const Receiver> receivers) {
    ProgressBar bar("exact AO");
    engine::RunOptions run;
    run.progress = bar.callback();
    Result<std::vector<float>> ao = engine->ao(receivers, run);
    if (ao) return std::move(*ao);
    if (!exact_error) exact_error = ao.error();
    return std::vector<float>(receivers.size(), 1.0f);
  };
  // RT-SVAO's column rays: every crossing, by Embree's nearest hits (either face).
  ssao::SegmentHits hits;
  if (std::find(options->methods.begin(), options->methods.end(), ssao::Method::RtSvaoRays) != options->methods.end()) {
    Result<ssao::SegmentHits> embree_hits = ssao::embree_segment_hits(*scene);
    if (!embree_hits) return report(embree_hits.error());
    hits = std::move(*embree_hits);
  }
  const ssao::Comparison comparison =
      ssao::compare_scene(*scene, *camera, o.camera.width, *height, *options, o.stereo, exact, hits);
  if (exact_error) return report(*exact_error);

  const std::filesystem::path dir(o.output);
  if (auto ok = write_compare_pictures(comparison, rays, dir); !ok) return report(ok.error());
  if (auto ok = write_compare_report(o, comparison, rays, options->stereo_ipd, dir); !ok) return report(ok.error());
  print_compare_summary(o, comparison, *scene, rays, options->stereo_ipd);
  return 0;
}

}  // namespace

Command add_compare_command(CLI::App& app) {
  auto o = std::make_shared<CompareCommandOptions>();
  o->rays.samples = 1024;
  o->camera.width = 480;  // with N = 1024 exact AO of the room stays well under a minute on 2 cores
  CLI::App* command = app.add_subcommand("compare", "Screen-space AO methods against the exact AO on the same G-buffer");
  add_scene_options(*command, o->scene);
  add_ray_options(*command, o->rays);
  add_camera_options(*command, o->camera);
  command->add_option("--masks", o->masks, "Exact AO's plane masks: lut or exact")->capture_default_str();
  command->add_option("--methods", o->methods,
                      "Comma-separated, or all: hbao, hbao+, vao, sdao (stochastic-depth HBAO), svao (SD-SVAO), rtsvao (RT-SVAO, exact AO at "
                      "flagged pixels), abuffer, shbao+ (stereo HBAO+, separable stereo filter), shbao+2d (full 2D stereo filter), "
                      "sdao+ (stochastic-depth HBAO+), mvsdao+ (multi-view SD-HBAO+), rtsvao-rays (RT-SVAO with column rays), "
                      "abuffer-m4, abuffer-m8 (compressed lists), abuffer-oit (transparent receivers)")
      ->capture_default_str();
  command->add_option("-o,--output", o->output, "Output folder")->capture_default_str();
  command->add_option("--directions", o->directions, "HBAO/HBAO+ directions per pixel")->capture_default_str();
  command->add_option("--steps", o->steps, "HBAO/HBAO+ steps per direction")->capture_default_str();
  command->add_option("--bias", o->bias, "HBAO angle bias (radians above the tangent) and HBAO+ NdotV bias")->capture_default_str();
  command->add_option("--angles", o->angles,
                      "HBAO family: horizon angles from the view-space XY plane (view, seed 000's Alg. 2) or from the tangent plane (tangent)")
      ->capture_default_str();
  command->add_flag("--cosine", o->cosine, "HBAO family with --angles tangent: cosine-weighted horizons (sin^2) instead of the papers' sin");
  command->add_option("--thickness", o->thickness, "VAO thickness tau of the halo model, 0 to 1")->capture_default_str();
  command->add_option("--sd-samples", o->sd_samples, "Stochastic depth samples per pixel S, 1 to 16")->capture_default_str();
  command->add_option("--sd-alpha", o->sd_alpha, "Stochastic depth keep probability alpha, (0, 1]")->capture_default_str();
  command->add_option("--blur", o->blur, "Bilateral blur radius in pixels (0: none)")->capture_default_str();
  command->add_option("--stereo", o->stereo, "Render left and right eyes this far apart (world units) and report inconsistency");
  command->add_option("--key", o->key, "Exact AO receiver keys: pixel (exao render's) or world (hash of the quantised position)")
      ->capture_default_str();
  command->add_option("--key-cell", o->key_cell, "World keys: grid cell as a fraction of the radius")->capture_default_str();
  command->add_option("--mv-angle", o->mv_angle, "mvsdao+: the secondary eye's turn about the camera's up axis, degrees")->capture_default_str();
  command->add_flag("--compress-whole-list", o->compress_whole_list,
                    "abuffer-m4/m8: apply seed 004's Eq. 5 to the whole list (default: keep its front half)");
  return [o, command](const Invocation&) { return command->parsed() ? run_compare(*o) : -1; };
}

}  // namespace exao::cli
