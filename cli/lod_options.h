#pragma once
// The raster backend's level of detail on the command line (paper Sec. 4.3, raster/lod.h):
// --lod auto|off|EPS1, --lod-levels L, --lod-k K, --lod-filter envelope|distance, turned into
// raster::LodOptions, and the levels built once per scene and radius and kept for reuse.

#include <map>
#include <memory>
#include <optional>
#include <string>

#include <CLI/CLI.hpp>

#include "core/camera.h"
#include "core/error.h"
#include "core/mask_set.h"
#include "core/pixel_receivers.h"
#include "core/progress.h"
#include "core/scene.h"
#include "lut/mask_engine.h"
#include "raster/lod.h"
#include "raster/occlusion.h"

namespace exao::cli {

struct LodCliOptions {
  std::string lod = "off";  // off | auto | a length (eps_1, world units)
  int levels = 1;
  float k = 3.0f;
  float overlap = 0.0f;
  std::string filter = "envelope";
};

void add_lod_options(CLI::App& app, LodCliOptions& options);

/// Checks the options (one-line errors naming the flag); nullopt for --lod off.
[[nodiscard]] Result<std::optional<raster::LodOptions>> check_lod_cli(const LodCliOptions& options);

/// World size of one pixel at the receivers' median view depth.
[[nodiscard]] float pixel_footprint(const PixelReceivers& pixels, const Camera& camera);

/// The LodOptions for radius r: eps_1 as given, or (auto) from r and the footprint.
[[nodiscard]] raster::LodOptions resolve_lod(const raster::LodOptions& checked, bool automatic, float radius,
                                             float footprint);

/// Levels built once per scene and kept in memory: simplified geometry (LodChain) once per
/// filter and eps_1 up to powers of 3, with a few levels to spare, so that every radius and every
/// eps_1 3^j reuses it; the assembled levels once per (radius, eps_1, L, k, overlap, filter).
class LodCache {
 public:
  explicit LodCache(const Scene& scene) : scene_(&scene) {}
  /// The levels for `radius` and `options`; `built` is set when this call built them.
  [[nodiscard]] const raster::LodScene& get(float radius, const raster::LodOptions& options,
                                            const ProgressCallback& progress = {}, bool* built = nullptr);

 private:
  const Scene* scene_;
  std::vector<std::unique_ptr<raster::LodChain>> chains_;
  std::map<std::tuple<float, float, int, float, int, float>, std::unique_ptr<raster::LodScene>> levels_;
};

/// The raster backend's masks of `pixels` with the levels of `lod`.
[[nodiscard]] MaskSet run_raster_lod(const Scene& scene, const raster::LodScene& lod, const lut::MaskEngine& engine,
                                     const PixelReceivers& pixels, const Camera& camera,
                                     raster::RasterOptions options, const ProgressCallback& progress = {},
                                     raster::RasterStats* stats = nullptr);

/// How AO from `masks` differs from AO from `reference` (same receivers): mean and max |dAO|,
/// the mean signed difference (AO - AO_reference: > 0 is brighter) and the share of receivers
/// whose AO is the same after 8-bit quantisation (the PNG preview's rounding).
struct AoError {
  double mean_abs = 0.0;
  double max_abs = 0.0;
  double bias = 0.0;
  double identical_8bit = 1.0;
};
[[nodiscard]] AoError ao_error(const MaskSet& reference, const MaskSet& masks);

/// One line describing the levels: eps, ranges, triangle counts, build time.
[[nodiscard]] std::string describe_lod(const raster::LodScene& lod, const raster::LodOptions& options, bool automatic);

}  // namespace exao::cli
