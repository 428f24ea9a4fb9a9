#pragma once
// exao::engine::LodCache: the raster method's levels of detail (paper Sec. 4.3, raster/lod.h) of
// one scene, built on first use and kept in memory, so that every engine over one Geometry
// (exao bench: every repeat, sample count and radius) reuses them. Two layers:
//  - the simplified geometry (raster::LodChain), the expensive part, once per filter and eps_1
//    up to powers of 3, with a few levels to spare, so that every radius and every eps_1 3^j
//    reuses it;
//  - the assembled levels (raster::LodScene) once per (radius, eps_1, L, k, overlap, filter).
// Thread safe: one build at a time.

#include <map>
#include <memory>
#include <mutex>
#include <tuple>
#include <vector>

#include "core/camera.h"
#include "core/error.h"
#include "core/pixel_receivers.h"
#include "core/progress.h"
#include "core/scene.h"
#include "raster/lod.h"

namespace exao::engine {

/// World size of one pixel at the receivers' median view depth (0 without receivers).
[[nodiscard]] float pixel_footprint(const PixelReceivers& pixels, const Camera& camera);

/// `options` with eps_1 resolved for radius r (world units): as given, or, when options.eps1 is
/// 0 (auto), raster::auto_lod_eps from r and the pixel footprint.
[[nodiscard]] raster::LodOptions resolve_lod(const raster::LodOptions& options, float radius, float footprint);

class LodCache {
 public:
  /// The scene must outlive the cache (the Geometry owns both).
  explicit LodCache(const Scene& scene) : scene_(&scene) {}

  struct Entry {
    const raster::LodScene* levels = nullptr;  // owned by the cache
    bool built = false;                        // this call built them
  };
  /// The levels for `radius` and `options` (eps1 resolved, > 0). Errors name the option
  /// (lod_eps1, lod_levels, ...).
  [[nodiscard]] Result<Entry> get(float radius, const raster::LodOptions& options, const ProgressCallback& progress = {});

 private:
  const Scene* scene_;
  std::mutex mutex_;
  std::vector<std::unique_ptr<raster::LodChain>> chains_;
  std::map<std::tuple<float, float, int, float, int, float>, std::unique_ptr<raster::LodScene>> levels_;
};

}  // namespace exao::engine
