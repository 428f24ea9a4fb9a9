#pragma once
// Options several subcommands share, parsed into plain structs and turned into the library
// engine's one Options (engine/options.h), which checks them.

#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "core/camera.h"
#include "core/error.h"
#include "core/scene.h"
#include "cli/option_flags.h"
#include "engine/engine.h"

namespace exao::cli {

struct SceneOptions {
  std::string scene = "room";  // a built-in scene's name or a file
  std::string sided = "auto";  // auto | one | two
  std::string cutouts = "on";  // on | off: glTF MASK materials cut out (core/cutouts.h)
  std::vector<std::string> blend{"opaque"};  // opaque | cutoff T | stochastic: BLEND materials
};

struct RayOptions {
  int samples = engine::Options{}.samples;
  std::string radius;          // a length, or a percentage of the diagonal; empty: the engine's default
  std::string falloff = "constant";
  std::optional<float> offset; // origin offset; default 1e-4 of the diagonal
  int threads = 0;             // 0: all cores
};

struct CameraOptions {
  std::string camera;          // a file camera's name or index
  std::vector<float> eye;      // X,Y,Z
  std::vector<float> target;   // X,Y,Z
  float fov = 60.0f;           // degrees, vertical; used with --eye/--target
  int width = 640;
  std::optional<int> height;   // default: width / the camera's aspect, or 480
};

// Defaults are the engine's (engine::Options), as text.
struct MethodOptions {
  std::string method = engine::method_name(engine::Options{}.method);
  std::string hybrid = bvh::hybrid_policy_name(engine::Options{}.hybrid);
  std::string masks = lut::mask_mode_name(engine::Options{}.masks);
  std::string embree_rays = embree_rays_name(engine::Options{}.embree.rays);
  bool embree_per_receiver = !engine::Options{}.embree.across_receivers;
  int table_resolution = engine::Options{}.table_resolution;
  int branching = engine::Options{}.bvh.branching;
  int leaf_size = engine::Options{}.bvh.max_leaf_size;
  float alpha = engine::Options{}.raster.alpha;
  std::string isa = "auto";  // the mask kernels' instruction set (core/isa.h)
};

void add_scene_options(CLI::App& app, SceneOptions& options);
void add_ray_options(CLI::App& app, RayOptions& options);
void add_camera_options(CLI::App& app, CameraOptions& options);
void add_method_options(CLI::App& app, MethodOptions& options);
/// The shape of the structures the methods build: the look-up table's resolution, the BVH's
/// branching and leaf size (part of add_method_options; `exao bench` takes them alone).
void add_structure_options(CLI::App& app, MethodOptions& options);

/// Opens the scene and prints what the loader skipped (one line each) to stderr.
[[nodiscard]] Result<Scene> open_scene(const SceneOptions& options);
/// Prints the loader's notes about `name` (skipped triangles, and the rest) to stderr.
void print_load_report(const std::string& name, const LoadReport& report);

/// "0.5" is a length; "5%" is 5 percent of the diagonal; "" the engine's default. Syntax only:
/// the engine checks the value.
[[nodiscard]] Result<engine::Length> parse_radius(const std::string& text);
[[nodiscard]] Result<Sidedness> parse_sidedness(const std::string& text);
/// --cutouts and --blend ("opaque", "cutoff T" or "stochastic") as the engine's policy, checked.
[[nodiscard]] Result<CutoutPolicy> parse_cutout_policy(const SceneOptions& scene);

/// The engine's options from the parsed flags, checked (engine::check_options): errors name
/// the option (report() prints its flag).
[[nodiscard]] Result<engine::Options> make_options(const SceneOptions& scene, const RayOptions& rays,
                                                   const MethodOptions& method);

/// Notes on stderr about settings that are legal but almost certainly not what was meant, once
/// per command with the engine it built: print_thread_note and print_ray_notes.
void print_option_notes(const engine::Engine& engine);
/// A note when `threads` is more than the machine's hardware threads.
void print_thread_note(int threads);
/// A note when the engine's radius is over 10x the scene's diagonal, or not longer than the ray
/// origin offset.
void print_ray_notes(const engine::Engine& engine);

/// --camera, else --eye/--target, else the file's first camera, else a view framing the scene.
[[nodiscard]] Result<Camera> choose_camera(const CameraOptions& options, const Scene& scene);
[[nodiscard]] Result<int> image_height(const CameraOptions& options, const Camera& camera);

/// A camera and an image size: choose_camera and image_height together.
struct View {
  Camera camera;
  int width = 0;
  int height = 0;
};
[[nodiscard]] Result<View> choose_view(const CameraOptions& options, const Scene& scene);

/// Refuses an output path that names the input file (inputs are never overwritten), or that
/// exists and is not a regular file (a folder, device, FIFO or socket; symbolic links are followed).
[[nodiscard]] Result<void> check_output(const std::string& output, const std::string& input);

/// Prints the work counters: per receiver (bvh), and the culling stages (raster).
/// The counters, naming the instruction set the kernels ran at (`isa`: the engine's option, or
/// the default level when unset).
void print_stats(const engine::Stats& stats, std::optional<Isa> isa);

}  // namespace exao::cli
