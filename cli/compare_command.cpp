// exao compare: the screen-space AO methods of the seeds (ssao/) against exao's exact AO on the
// same G-buffer pixels: error statistics, times, pictures, JSON and a Markdown table; with
// --stereo, each method's inconsistency between the eyes (seed 003). A thin layer: the methods
// and the measurements are in ssao/, the exact AO is the bvh method of the library engine (engine/).

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>
#include <sstream>
#include <string_view>
#include <utility>

#include <nlohmann/json.hpp>
#include <tbb/global_control.h>

#include "cli/commands.h"
#include "core/cutouts.h"
#include "cli/option_flags.h"
#include "cli/common_options.h"
#include "cli/progress_bar.h"
#include "core/atomic_write.h"
#include "core/embree_reference.h"
#include "io/image_io.h"
#include "engine/engine.h"
#include "ssao/compare.h"
#include "ssao/contact_sheet.h"
#include "ssao/error_stats.h"
#include "ssao/grazing_box.h"
#include "ssao/stereo.h"

namespace exao::cli {
namespace {

struct CompareCommandOptions {
  SceneOptions scene;
  RayOptions rays;
  CameraOptions camera;
  std::string masks = "lut";
  std::string methods = "all";
  std::string output = "compare";
  int directions = 8;
  int steps = 4;
  double bias = 0.1;
  bool cosine = false;
  std::string angles = "view";
  double thickness = 0.5;
  int sd_samples = 4;
  double sd_alpha = 0.2;
  int blur = 4;
  std::optional<double> stereo;
  std::string key = "pixel";
  double key_cell = 0.25;
  double mv_angle = 45.0;
  bool compress_whole_list = false;
};

Result<void> write_text(const std::string& text, const std::string& path) {
  return write_atomically(path, [&](const std::string& temp) -> Result<void> {
    std::ofstream out(temp, std::ios::binary);
    out << text;
    out.close();
    if (!out) return fail(path + ": cannot write");
    return {};
  });
}

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

std::string slug(const std::string& name) {
  std::string out;
  for (const char c : name) out += c == '+' ? std::string("-plus") : std::string(1, c);
  return out;
}

AoImage ao_image(const ssao::View& view, const std::vector<float>& ao) {
  AoImage image;
  image.width = view.width;
  image.height = view.height;
  image.ao = ao;
  image.coverage.resize(ao.size());
  for (std::size_t p = 0; p < ao.size(); ++p) image.coverage[p] = view.valid[p] ? 1.0f : 0.0f;
  return image;
}

Result<void> write_ao(const ssao::View& view, const std::vector<float>& ao, const std::filesystem::path& base) {
  const AoImage image = ao_image(view, ao);
  if (auto ok = write_exr(image, base.string() + ".exr"); !ok) return ok;
  return write_png(image, base.string() + ".png");
}

Result<void> write_rgb(const ssao::RgbImage& image, const std::string& path) {
  return write_png_bytes(image.rgb, image.width, image.height, 3, path);
}

std::string percent(double share) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1f%%", 100.0 * share);
  return text;
}

std::string fixed(double v, int digits) {
  char text[32];
  std::snprintf(text, sizeof text, "%.*f", digits, v);
  return text;
}

int run_compare(const CompareCommandOptions& o) {
  Result<std::vector<ssao::Method>> methods = ssao::parse_methods(o.methods);
  if (!methods) return report(as_flag_error(methods.error()));
  if (o.stereo && !(std::isfinite(*o.stereo) && *o.stereo > 0.0)) return report(Error{"--stereo: the eye distance must be greater than 0"});
  if (o.angles != "view" && o.angles != "tangent") return report(Error{"--angles: must be view or tangent, got '" + o.angles + "'"});
  if (o.key != "pixel" && o.key != "world") return report(Error{"--key: must be pixel or world, got '" + o.key + "'"});
  if (!(std::isfinite(o.key_cell) && o.key_cell > 0.0)) return report(Error{"--key-cell: must be greater than 0"});
  if (auto ok = check_output(o.output, o.scene.scene); !ok) return report(ok.error());
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

  // seed 000's Fig. 3 case is a scene of the comparison's own (ssao/grazing_box.h).
  Result<Scene> scene = o.scene.scene == ssao::kGrazingBoxName ? Result<Scene>(ssao::make_grazing_box()) : open_scene(o.scene);
  if (!scene) return report(scene.error());
  // The G-buffer sees the sidedness the exact AO uses.
  apply_sidedness(*scene, engine_options->sidedness);
  scene->cutouts = apply_cutout_policy(scene->cutouts, engine_options->cutouts);  // the A-buffer reads them too
  Result<engine::Engine> engine = engine::Engine::build(*scene, *engine_options, engine::Receivers::Points);
  if (!engine) return report(engine.error());
  print_option_notes(*engine);
  const ShadowRays* rays = &engine->rays();
  Result<Camera> camera = choose_camera(o.camera, *scene);
  if (!camera) return report(camera.error());
  Result<int> height = image_height(o.camera, *camera);
  if (!height) return report(height.error());

  ssao::CompareOptions options;
  options.methods = *methods;
  options.settings.radius = rays->radius;
  options.settings.falloff = rays->pattern.falloff;
  options.settings.blur_radius = o.blur;
  options.hbao.directions = options.hbao_plus.directions = o.directions;
  options.hbao.steps = options.hbao_plus.steps = o.steps;
  options.hbao.bias = options.hbao_plus.bias = o.bias;
  options.hbao.cosine = o.cosine;
  options.hbao.angles = o.angles == "tangent" ? ssao::Angles::Tangent : ssao::Angles::ViewPlane;
  options.vao.thickness = o.thickness;
  options.stochastic.samples = o.sd_samples;
  options.stochastic.alpha = o.sd_alpha;
  if (o.key == "world") options.world_key_cell = static_cast<float>(o.key_cell * rays->radius);
  options.multiview.angle_degrees = o.mv_angle;
  options.keep_front_half = !o.compress_whole_list;
  // Stereo HBAO+'s other eye: --stereo's, or a tenth of the radius to the right.
  options.stereo_ipd = o.stereo ? *o.stereo : 0.1 * static_cast<double>(rays->radius);
  if (auto ok = ssao::check(options); !ok) return report(as_flag_error(ok.error()));

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
  std::optional<EmbreeScene> embree;
  ssao::SegmentHits hits;
  if (std::find(options.methods.begin(), options.methods.end(), ssao::Method::RtSvaoRays) != options.methods.end()) {
    Result<EmbreeScene> built = EmbreeScene::build(*scene);
    if (!built) return report(built.error());
    embree.emplace(std::move(*built));
    hits = ssao::segment_hits_by_closest([&embree](const glm::dvec3& origin, const glm::dvec3& direction) -> std::optional<double> {
      const auto hit = embree->closest_hit(glm::vec3(origin), glm::vec3(direction));
      if (!hit) return std::nullopt;
      return static_cast<double>(hit->distance);
    });
  }

  std::vector<Camera> cameras = {*camera};
  if (o.stereo) {
    const auto eyes = ssao::stereo_cameras(*camera, *o.stereo);
    cameras = {eyes.first, eyes.second};
    options.stereo_eyes = eyes;
  }
  std::vector<ssao::ViewResult> views;
  for (const Camera& c : cameras) views.push_back(ssao::compare_view(*scene, c, o.camera.width, *height, options, exact, hits));
  if (exact_error) return report(*exact_error);
  const ssao::ViewResult& main = views.front();
  std::optional<ssao::Correspondence> pairs;
  if (o.stereo) pairs = ssao::correspond(views[0].view, views[1].view);

  // Pictures: AO, heat maps, the contact sheet.
  const std::filesystem::path dir(o.output);
  if (auto ok = write_ao(main.view, main.exact, dir / "exact"); !ok) return report(ok.error());
  std::vector<ssao::RgbImage> greys, heats;
  greys.reserve(main.methods.size() + 1);
  heats.reserve(main.methods.size());
  greys.push_back(ssao::grey_image(main.exact, main.view.valid, main.view.width, main.view.height));
  std::vector<AoError> stats;
  for (const ssao::MethodResult& m : main.methods) {
    const std::string name = slug(ssao::compare_method_name(m.method));
    if (auto ok = write_ao(main.view, m.ao, dir / name); !ok) return report(ok.error());
    heats.push_back(ssao::heat_map(m.ao, main.exact, main.view.valid, main.view.width, main.view.height));
    if (auto ok = write_rgb(heats.back(), (dir / (name + "-error.png")).string()); !ok) return report(ok.error());
    greys.push_back(ssao::grey_image(m.ao, main.view.valid, main.view.width, main.view.height));
    stats.push_back(ssao::error_stats(m.ao, main.exact, main.view.valid));
  }
  std::vector<ssao::SheetCell> cells;
  const ssao::RgbImage legend = ssao::heat_map_legend(main.view.width, main.view.height);
  cells.push_back({"EXACT N=" + std::to_string(rays->count()), &greys[0], &legend});
  for (std::size_t i = 0; i < main.methods.size(); ++i) {
    // Label and mean abs error: at most 20 characters fit over a 240-pixel tile.
    cells.push_back({std::string(ssao::method_label(main.methods[i].method)) + " " + fixed(stats[i].mean_abs(), 3), &greys[i + 1], &heats[i]});
  }
  if (auto ok = write_rgb(ssao::contact_sheet(cells, 4, 320), (dir / "contact-sheet.png").string()); !ok) return report(ok.error());

  // The table and the JSON.
  nlohmann::json j;
  j["scene"] = o.scene.scene;
  j["width"] = main.view.width;
  j["height"] = main.view.height;
  j["pixels"] = main.view.receivers.receivers.size();
  j["radius"] = rays->radius;
  j["falloff"] = falloff_name(rays->pattern.falloff);
  j["samples"] = rays->count();
  j["key"] = o.key;
  j["parameters"] = {{"directions", o.directions}, {"steps", o.steps}, {"bias", o.bias}, {"angles", o.angles}, {"cosine", o.cosine},
                     {"thickness", o.thickness}, {"sd_samples", o.sd_samples}, {"sd_alpha", o.sd_alpha}, {"blur", o.blur}};
  j["gbuffer_seconds"] = main.gbuffer_seconds;
  j["abuffer_seconds"] = main.fragment_seconds;
  j["exact"] = {{"seconds", main.exact_seconds}};
  std::ostringstream md;
  md << "| method | mean abs error | bias | RMSE | within 1/255 | within 1/16 | time (s) |" << (o.stereo ? " stereo E |" : "") << "\n";
  md << "|---|---|---|---|---|---|---|" << (o.stereo ? "---|" : "") << "\n";
  const auto stereo_of = [&](std::size_t k) -> std::optional<ssao::Inconsistency> {
    if (!pairs) return std::nullopt;
    if (k == 0) return ssao::inconsistency(*pairs, views[0].exact, views[1].exact);
    return ssao::inconsistency(*pairs, views[0].methods[k - 1].ao, views[1].methods[k - 1].ao);
  };
  const auto stereo_json = [](const ssao::Inconsistency& e) {
    return nlohmann::json{{"mean", e.mean}, {"rmse", e.rmse}, {"within_255", e.within_255}, {"pixels", e.pixels}, {"share", e.share}};
  };
  if (const auto e = stereo_of(0)) j["exact"]["stereo"] = stereo_json(*e);
  md << "| exact (bvh, N = " << rays->count() << ") | 0 | 0 | 0 | 100% | 100% | " << fixed(main.exact_seconds, 3) << " |"
     << (pairs ? " " + fixed(stereo_of(0)->mean, 4) + " |" : "") << "\n";
  j["methods"] = nlohmann::json::array();
  std::vector<std::string> versus_full;
  for (std::size_t i = 0; i < main.methods.size(); ++i) {
    const ssao::MethodResult& m = main.methods[i];
    const AoError& s = stats[i];
    nlohmann::json row{{"name", ssao::compare_method_name(m.method)}, {"label", ssao::method_label(m.method)},
                       {"mean_abs", s.mean_abs()}, {"bias", s.bias()}, {"rmse", s.rmse()}, {"within_255", s.within_255_share()},
                       {"within_16", s.within_16_share()}, {"seconds", m.seconds},
                       {"map_seconds", m.map_seconds}};
    if (m.method == ssao::Method::SdSvao || m.method == ssao::Method::RtSvao || m.method == ssao::Method::RtSvaoRays) {
      row["flagged_pixels"] = m.flagged;
    }
    if (ssao::is_stereo(m.method)) row["stereo_pass"] = {{"reprojected_pixels", m.reprojected}, {"hole_pixels", m.holes}, {"both_eyes", true}};
    if (m.fragments) row["fragments"] = m.fragments;
    // A variant against the row it approximates, when both ran: the compressed lists and the
    // transparent receivers against the A-buffer (seed 004 Sec. V-A), the 2D stereo filter
    // against the separable one (seed 003 Fig. 7).
    const ssao::Method reference = m.method == ssao::Method::StereoHbaoPlus2d ? ssao::Method::StereoHbaoPlus : ssao::Method::Abuffer;
    if (ssao::list_nodes(m.method) > 0 || m.method == ssao::Method::AbufferOit || m.method == ssao::Method::StereoHbaoPlus2d) {
      for (const ssao::MethodResult& full : main.methods) {
        if (full.method != reference) continue;
        const AoError d = ssao::error_stats(m.ao, full.ao, main.view.valid);
        const double ratio = full.seconds > 0.0 ? m.seconds / full.seconds : 0.0;
        row["against"] = {{"method", ssao::compare_method_name(reference)}, {"mean_abs", d.mean_abs()}, {"rmse", d.rmse()},
                          {"within_255", d.within_255_share()}, {"time_ratio", ratio}};
        versus_full.push_back(std::string(ssao::method_label(m.method)) + ": " +
                              (m.fragments ? std::to_string(m.fragments) + " fragments, " : std::string()) + "mean |AO - " +
                              ssao::method_label(reference) + "| " + fixed(d.mean_abs(), 5) + ", RMSE " + fixed(d.rmse(), 5) + ", " +
                              percent(d.within_255_share()) + " within 1/255, time " + fixed(m.seconds, 3) + " s (" + fixed(ratio, 2) + "x)");
      }
    }
    const auto e = stereo_of(i + 1);
    if (e) row["stereo"] = stereo_json(*e);
    j["methods"].push_back(row);
    md << "| " << ssao::method_label(m.method) << " | " << fixed(s.mean_abs(), 4) << " | " << (s.bias() >= 0 ? "+" : "") << fixed(s.bias(), 4)
       << " | " << fixed(s.rmse(), 4) << " | " << percent(s.within_255_share()) << " | " << percent(s.within_16_share()) << " | " << fixed(m.seconds, 3) << " |"
       << (e ? " " + fixed(e->mean, 4) + " |" : "") << "\n";
  }
  if (pairs) j["stereo"] = {{"ipd", *o.stereo}, {"pixels_compared", pairs->left.size()}, {"left_pixels", pairs->left_visible}};
  j["stereo_hbao_plus_ipd"] = options.stereo_ipd;
  j["other_eye_gbuffer_seconds"] = main.other_eye_seconds;
  if (main.secondary) {
    const Camera& c = *main.secondary;
    j["secondary_camera"] = {{"eye", {c.eye.x, c.eye.y, c.eye.z}}, {"forward", {c.forward.x, c.forward.y, c.forward.z}},
                             {"yfov_degrees", glm::degrees(c.yfov)}, {"angle_degrees", o.mv_angle}};
  }
  if (auto ok = write_text(j.dump(2) + "\n", (dir / "compare.json").string()); !ok) return report(ok.error());
  if (auto ok = write_text(md.str(), (dir / "compare.md").string()); !ok) return report(ok.error());

  std::printf("%s: %zu triangles, %dx%d, %zu pixels, r=%g, N=%d, G-buffer %.3f s, A-buffer %.3f s -> %s/\n",
              o.scene.scene.c_str(), scene->triangle_count(), main.view.width, main.view.height,
              main.view.receivers.receivers.size(), static_cast<double>(rays->radius), rays->count(), main.gbuffer_seconds,
              main.fragment_seconds, o.output.c_str());
  std::printf("%s", md.str().c_str());
  for (const std::string& line : versus_full) std::printf("%s\n", line.c_str());
  if (main.secondary) {
    const Camera& c = *main.secondary;
    std::printf("MV-SD-HBAO+: secondary eye (%g, %g, %g), turned %g degrees, field of view %.1f degrees\n", static_cast<double>(c.eye.x),
                static_cast<double>(c.eye.y), static_cast<double>(c.eye.z), o.mv_angle, static_cast<double>(glm::degrees(c.yfov)));
  }
  for (const ssao::MethodResult& m : main.methods) {
    if (!ssao::is_stereo(m.method)) continue;
    std::printf("%s: other eye %g to the side, %zu pixels reprojected, %zu holes evaluated (both eyes timed)\n", ssao::method_label(m.method),
                options.stereo_ipd, m.reprojected, m.holes);
    break;
  }
  if (pairs) {
    std::printf("stereo: IPD %g, %zu of %zu left pixels seen by both eyes; E = mean |AO_left - AO_right reprojected|, key %s\n",
                *o.stereo, pairs->left.size(), pairs->left_visible, o.key.c_str());
  }
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
