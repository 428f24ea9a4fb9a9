#pragma once
// Options several subcommands share, parsed into plain structs and turned into library inputs.

#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "core/camera.h"
#include "core/error.h"
#include "core/scene.h"
#include "core/shadow_rays.h"
#include "cli/backends.h"

#include <memory>
#include <tbb/global_control.h>

namespace exao::cli {

struct SceneOptions {
  std::string scene = "room";  // a built-in scene's name or a file
  std::string sided = "auto";  // auto | one | two
};

struct RayOptions {
  int samples = 128;
  std::string radius = "5%";   // a length, or a percentage of the bounding-box diagonal
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

struct MethodOptions {
  std::string method = "bvh";  // embree | brute | bvh | raster
  std::string masks = "lut";   // lut | exact
  std::string embree_rays = "packet16";
  bool embree_per_receiver = false;  // packets of one receiver's samples instead of one sample of neighbours
  int table_resolution = 0;    // 0: the default for N
  int branching = 4;
  int leaf_size = 8;
  float alpha = 0.2f;           // raster: R / r above which a triangle gets a prism, else a billboard
};

void add_scene_options(CLI::App& app, SceneOptions& options);
void add_ray_options(CLI::App& app, RayOptions& options);
void add_camera_options(CLI::App& app, CameraOptions& options);
void add_method_options(CLI::App& app, MethodOptions& options);

/// Opens the scene, applies --sided and prints what the loader skipped (one line each) to stderr.
[[nodiscard]] Result<Scene> open_scene(const SceneOptions& options);

/// "0.5" is a length; "5%" is 5 percent of `diagonal`.
[[nodiscard]] Result<float> parse_radius(const std::string& text, float diagonal);

/// Refuses a radius or offset beyond 1e17 (core/coordinate_limit.h); prints a note on stderr for
/// a radius over 10x the scene's diagonal, or not longer than the offset.
[[nodiscard]] Result<void> check_radius(float radius, float diagonal, float offset);

/// The pattern and radius of section 1, for this scene.
[[nodiscard]] Result<ShadowRays> make_rays(const RayOptions& options, const Scene& scene);

/// --camera, else --eye/--target, else the file's first camera, else a view framing the scene.
[[nodiscard]] Result<Camera> choose_camera(const CameraOptions& options, const Scene& scene);
[[nodiscard]] Result<int> image_height(const CameraOptions& options, const Camera& camera);

/// Refuses an output path that names the input file (inputs are never overwritten), or that
/// exists and is not a regular file (a folder, device, FIFO or socket; symbolic links are followed).
[[nodiscard]] Result<void> check_output(const std::string& output, const std::string& input);

/// The backend settings of --masks, --embree-rays, --table-resolution and --branching.
[[nodiscard]] Result<BackendOptions> make_backend_options(const MethodOptions& options);

/// --threads: 0 (all cores) up to oneTBB's ceiling (256, or 4x the cores), else an error; a note
/// on stderr when it is more than the machine's hardware threads.
[[nodiscard]] Result<void> check_threads(int threads);

/// Checks `threads` (check_threads) and caps TBB's worker threads when threads > 0; keep the
/// result alive while working.
[[nodiscard]] Result<std::unique_ptr<tbb::global_control>> thread_limit(int threads);

/// Prints BVH work counters per receiver.
void print_stats(const BackendStats& stats);

/// Prints "exao: <message>" on stderr and returns the exit status for bad input.
int report(const Error& error);

}  // namespace exao::cli
