#include "cli/common_options.h"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <thread>

#include "cli/progress_bar.h"
#include "core/coordinate_limit.h"
#include "core/cutouts.h"
#include "core/file_kind.h"
#include "io/load_scene.h"

namespace exao::cli {

void add_scene_options(CLI::App& app, SceneOptions& options) {
  app.add_option("scene", options.scene, "A built-in scene (room, plane-pair, sphere-on-plane, hidden-box, corners, foliage) or a .gltf/.glb/.obj/.ply/.off/.stl file")
      ->capture_default_str();
  app.add_option("--sided", options.sided, "Triangle sidedness: auto (glTF doubleSided; other formats two-sided), one, two")
      ->check(CLI::IsMember({"auto", "one", "two"}))
      ->capture_default_str();
  app.add_option("--cutouts", options.cutouts,
                 "glTF alphaMode MASK cut-outs: on (rays pass where the base colour alpha is below alphaCutoff) or off (every triangle opaque)")
      ->check(CLI::IsMember({"on", "off"}))
      ->capture_default_str();
  app.add_option("--blend", options.blend,
                 "glTF alphaMode BLEND materials: opaque, cutoff T (a cut-out at alpha T) or stochastic (blocks with probability alpha)")
      ->expected(1, 2)
      ->capture_default_str();
}

void add_ray_options(CLI::App& app, RayOptions& options) {
  app.add_option("-n,--samples", options.samples, "Rays per receiver: a multiple of 32 from 32 to 1024")->capture_default_str();
  app.add_option("-r,--radius", options.radius,
                 "AO radius: a length, or a percentage of the bounding-box diagonal (default " +
                     std::to_string(static_cast<int>(engine::kDefaultRadius.value)) + "%)");
  app.add_option("--falloff", options.falloff, "constant, linear or quadratic")->capture_default_str();
  app.add_option("--offset", options.offset, "Ray origin offset along the normal (default 1e-4 of the diagonal)");
  app.add_option("-j,--threads", options.threads, "Worker threads (0: all cores)")->capture_default_str();
}

void add_camera_options(CLI::App& app, CameraOptions& options) {
  app.add_option("--camera", options.camera, "A camera of the file, by name or index");
  app.add_option("--eye", options.eye, "Camera position X,Y,Z")->delimiter(',')->expected(3);
  app.add_option("--target", options.target, "Point the camera looks at X,Y,Z")->delimiter(',')->expected(3);
  app.add_option("--fov", options.fov, "Vertical field of view in degrees, with --eye")->capture_default_str();
  app.add_option("-W,--width", options.width, "Image width in pixels")->capture_default_str();
  app.add_option("-H,--height", options.height, "Image height in pixels (default: from the camera's aspect, or 480)");
}

void add_structure_options(CLI::App& app, MethodOptions& options) {
  app.add_option("--table-resolution", options.table_resolution, "Look-up table cells per side (0: the default for N)")
      ->capture_default_str();
  app.add_option("--branching", options.branching, "BVH children per node: 2 or 4")->capture_default_str();
  app.add_option("--leaf-size", options.leaf_size, "Most triangles per BVH leaf: 1 to 8")->capture_default_str();
}

void add_method_options(CLI::App& app, MethodOptions& options) {
  app.add_option("--method", options.method,
                 "auto (masks, then Embree for the rays masks do not decide cheaply: Embree's answer on every ray), "
                 "bvh (the paper's BVH traversal alone), raster (rasterization, camera views), brute (every triangle) "
                 "or embree (rays)")
      ->capture_default_str();
  app.add_option("--hybrid", options.hybrid,
                 "auto: adaptive (its cost model), masks (masks to the end) or rays (Embree only); the same answer")
      ->capture_default_str();
  app.add_option("--masks", options.masks, "Plane masks from the look-up table (lut) or exact tests (exact)")
      ->capture_default_str();
  app.add_option("--embree-rays", options.embree_rays, "single, packet4, packet8 or packet16")->capture_default_str();
  app.add_flag("--embree-per-receiver", options.embree_per_receiver,
               "Embree packets hold neighbouring samples of one receiver (default: one sample of neighbouring receivers)");
  add_structure_options(app, options);
  app.add_option("--isa", options.isa,
                 "Instruction set of the mask kernels: auto (EXAO_ISA, else the best this CPU runs), scalar, sse2, "
                 "sse4, avx2 or avx512; every one gives the same bits")
      ->capture_default_str();
  app.add_option("--alpha", options.alpha, "raster: R/r above which a triangle's volume is a prism, else a billboard")
      ->capture_default_str();
}

void print_stats(const engine::Stats& stats, std::optional<Isa> isa) {
  if (stats.raster.receivers) std::printf("%s", raster::format_stats(stats.raster).c_str());
  std::printf("%s", bvh::format_stats(stats.traversal, isa ? *isa : default_isa()).c_str());
}

void print_load_report(const std::string& name, const LoadReport& r) {
  if (r.zero_area_skipped) std::fprintf(stderr, "exao: %s: skipped %zu zero-area triangles of %zu\n", name.c_str(), r.zero_area_skipped, r.triangles_read);
  if (r.non_finite_skipped) std::fprintf(stderr, "exao: %s: skipped %zu triangles with NaN, infinite or huge (beyond +-1e17) vertices\n", name.c_str(), r.non_finite_skipped);
  for (const std::string& note : r.notes) std::fprintf(stderr, "exao: %s: %s\n", name.c_str(), note.c_str());
}

Result<Scene> open_scene(const SceneOptions& options) {
  Result<Scene> scene = [&] {
    ProgressBar bar("load");
    return exao::open_scene(options.scene, bar.callback());
  }();
  if (scene) print_load_report(options.scene, scene->report);
  return scene;
}

Result<Sidedness> parse_sidedness(const std::string& text) {
  if (text == "auto") return Sidedness::Auto;
  if (text == "one") return Sidedness::One;
  if (text == "two") return Sidedness::Two;
  return fail("sidedness: must be auto, one or two, got '" + text + "'");
}

Result<CutoutPolicy> parse_cutout_policy(const SceneOptions& scene) {
  CutoutPolicy policy;
  policy.enabled = scene.cutouts != "off";
  if (scene.blend.empty()) return policy;
  Result<BlendRule> rule = parse_blend_rule(scene.blend[0]);
  if (!rule) return std::unexpected(rule.error());
  policy.blend = *rule;
  if ((policy.blend == BlendRule::Cutoff) != (scene.blend.size() == 2)) {
    return fail("blend: 'cutoff' takes a threshold (cutoff T, T in [0, 1]); opaque and stochastic take none");
  }
  if (scene.blend.size() == 2) {
    float value = 0.0f;
    std::size_t used = 0;
    try {
      value = std::stof(scene.blend[1], &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != scene.blend[1].size()) return fail("blend_cutoff: '" + scene.blend[1] + "' is not a number");
    policy.blend_cutoff = value;
  }
  if (auto ok = check_policy(policy); !ok) return std::unexpected(ok.error());
  return policy;
}

Result<engine::Length> parse_radius(const std::string& text) {
  if (text.empty()) return engine::kDefaultRadius;
  const bool percent = text.back() == '%';
  const std::string number = percent ? text.substr(0, text.size() - 1) : text;
  float value = 0.0f;
  std::size_t used = 0;
  try {
    value = std::stof(number, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != number.size()) return fail("radius: '" + text + "' is not a length or a percentage");
  return engine::Length{value, percent};
}

Result<engine::Options> make_options(const SceneOptions& scene, const RayOptions& rays, const MethodOptions& method) {
  engine::Options out;
  Result<engine::Length> radius = parse_radius(rays.radius);
  if (!radius) return std::unexpected(radius.error());
  out.radius = *radius;
  out.samples = rays.samples;
  Result<Falloff> falloff = parse_falloff(rays.falloff);
  if (!falloff) return std::unexpected(falloff.error());
  out.falloff = *falloff;
  out.origin_offset = rays.offset;
  Result<Sidedness> sided = parse_sidedness(scene.sided);
  if (!sided) return std::unexpected(sided.error());
  out.sidedness = *sided;
  Result<CutoutPolicy> cutouts = parse_cutout_policy(scene);
  if (!cutouts) return std::unexpected(cutouts.error());
  out.cutouts = *cutouts;
  out.threads = rays.threads;
  Result<engine::Method> m = engine::parse_method(method.method);
  if (!m) return std::unexpected(m.error());
  out.method = *m;
  Result<bvh::HybridPolicy> hybrid = bvh::parse_hybrid_policy(method.hybrid);
  if (!hybrid) return std::unexpected(hybrid.error());
  out.hybrid = *hybrid;
  Result<lut::MaskMode> masks = lut::parse_mask_mode(method.masks);
  if (!masks) return std::unexpected(masks.error());
  out.masks = *masks;
  Result<EmbreeRays> embree_rays = parse_embree_rays(method.embree_rays);
  if (!embree_rays) return std::unexpected(embree_rays.error());
  out.embree.rays = *embree_rays;
  out.embree.across_receivers = !method.embree_per_receiver;
  out.table_resolution = method.table_resolution;
  out.bvh.branching = method.branching;
  out.bvh.max_leaf_size = method.leaf_size;
  out.raster.alpha = method.alpha;
  Result<std::optional<Isa>> isa = parse_isa(method.isa);
  if (!isa) return std::unexpected(isa.error());
  out.isa = *isa;
  if (auto ok = engine::check_options(out); !ok) return std::unexpected(ok.error());
  return out;
}

void print_thread_note(int threads) {
  const unsigned cores = std::thread::hardware_concurrency();
  if (cores > 0 && threads > 0 && static_cast<unsigned>(threads) > cores) {
    std::fprintf(stderr, "exao: note: --threads %d is more than the %u hardware threads of this machine\n", threads, cores);
  }
}

void print_ray_notes(const engine::Engine& engine) {
  const float radius = engine.radius();
  const float offset = engine.origin_offset();
  const float diagonal = engine.geometry().bounds().diagonal();
  if (diagonal > 0.0f && radius > 10.0f * diagonal) {
    std::fprintf(stderr, "exao: note: --radius %g is %.0f times the scene's diagonal (%g): every ray reaches across the whole scene\n",
                 static_cast<double>(radius), static_cast<double>(radius / diagonal), static_cast<double>(diagonal));
  } else if (radius <= offset) {
    std::fprintf(stderr, "exao: note: --radius %g is not longer than the ray origin offset (%g): rays start beyond their own reach of the surface\n",
                 static_cast<double>(radius), static_cast<double>(offset));
  }
}

void print_option_notes(const engine::Engine& engine) {
  print_thread_note(engine.options().threads);
  print_ray_notes(engine);
}

namespace {

// The camera a choice gave, unless Embree could not cast its rays (core/camera.h).
Result<Camera> checked(Camera camera, const std::string& what) {
  if (const std::string problem = camera_problem(camera); !problem.empty()) return fail(what + ": " + problem);
  return camera;
}

}  // namespace

Result<Camera> choose_camera(const CameraOptions& options, const Scene& scene) {
  if (!options.eye.empty() || !options.target.empty()) {
    if (options.eye.size() != 3 || options.target.size() != 3) return fail("--eye and --target: give both, as X,Y,Z");
    const glm::vec3 eye(options.eye[0], options.eye[1], options.eye[2]);
    const glm::vec3 target(options.target[0], options.target[1], options.target[2]);
    if (!within_coordinate_limit(eye)) return fail("--eye: each coordinate must be a finite number within +-1e17");
    if (!within_coordinate_limit(target)) return fail("--target: each coordinate must be a finite number within +-1e17");
    if (glm::length(glm::dvec3(target) - glm::dvec3(eye)) <= 0.0) return fail("--eye and --target: must be different points");
    if (!(options.fov > 0.0f && options.fov < 180.0f)) return fail("--fov: must be between 0 and 180 degrees");
    return checked(look_at(eye, target, options.fov), "--eye and --target");
  }
  if (!options.camera.empty()) {
    for (const Camera& camera : scene.cameras) {
      if (camera.name == options.camera) return checked(camera, "--camera " + options.camera);
    }
    unsigned long long index = 0;
    const char* first = options.camera.data();
    const char* last = first + options.camera.size();
    const auto [end, error] = std::from_chars(first, last, index);
    if (error == std::errc() && end == last && index < scene.cameras.size()) {
      return checked(scene.cameras[static_cast<std::size_t>(index)], "--camera " + options.camera);
    }
    return fail("--camera: the scene has no camera '" + options.camera + "' (it has " + std::to_string(scene.cameras.size()) + ")");
  }
  if (!scene.cameras.empty()) return checked(scene.cameras.front(), "the scene's camera '" + scene.cameras.front().name + "'");
  const float aspect = static_cast<float>(options.width) / static_cast<float>(options.height.value_or(std::max(1, options.width * 3 / 4)));
  return checked(frame_bounds(scene.bounds(), aspect), "the view that frames the scene");
}

Result<int> image_height(const CameraOptions& options, const Camera& camera) {
  int height = 480;
  if (options.height) {
    height = *options.height;
  } else if (camera.aspect && *camera.aspect > 0.0f) {
    height = std::max(1, static_cast<int>(std::lround(static_cast<float>(options.width) / *camera.aspect)));
  } else {
    height = std::max(1, options.width * 3 / 4);
  }
  if (options.width < 1 || height < 1 || options.width > 16384 || height > 16384) {
    return fail("--width/--height: the image must be from 1 to 16384 pixels on each side");
  }
  return height;
}

Result<View> choose_view(const CameraOptions& options, const Scene& scene) {
  Result<Camera> camera = choose_camera(options, scene);
  if (!camera) return std::unexpected(camera.error());
  Result<int> height = image_height(options, *camera);
  if (!height) return std::unexpected(height.error());
  return View{*camera, options.width, *height};
}

Result<void> check_output(const std::string& output, const std::string& input) {
  std::error_code ec;
  // Refused now rather than after the work; write_atomically refuses it again (core/atomic_write.h).
  if (std::filesystem::exists(std::filesystem::symlink_status(output, ec))) {
    if (const std::string problem = not_a_regular_file(output); !problem.empty()) {
      return fail(output + ": " + problem + "; refusing to replace it");
    }
  }
  if (std::filesystem::exists(input, ec) && std::filesystem::exists(output, ec) &&
      std::filesystem::equivalent(output, input, ec)) {
    return fail(output + ": is the input scene; refusing to overwrite it");
  }
  return {};
}

}  // namespace exao::cli
