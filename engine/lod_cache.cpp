#include "engine/lod_cache.h"

#include <algorithm>
#include <cmath>

#include <glm/glm.hpp>

namespace exao::engine {

float pixel_footprint(const PixelReceivers& pixels, const Camera& camera) {
  if (pixels.receivers.empty() || pixels.height <= 0) return 0.0f;
  std::vector<float> depth;
  depth.reserve(pixels.receivers.size());
  for (const Receiver& r : pixels.receivers) depth.push_back(glm::dot(r.position - camera.eye, camera.forward));
  auto middle = depth.begin() + static_cast<std::ptrdiff_t>(depth.size() / 2);
  std::nth_element(depth.begin(), middle, depth.end());
  return *middle * 2.0f * std::tan(0.5f * camera.yfov) / static_cast<float>(pixels.height);
}

raster::LodOptions resolve_lod(const raster::LodOptions& options, float radius, float footprint) {
  raster::LodOptions out = options;
  if (options.eps1 == 0.0f) out.eps1 = raster::auto_lod_eps(radius, footprint, options.levels, options.k);
  return out;
}

Result<LodCache::Entry> LodCache::get(float radius, const raster::LodOptions& options, const ProgressCallback& progress) {
  if (auto ok = raster::check_lod_options(options); !ok) return std::unexpected(ok.error());
  const std::lock_guard lock(mutex_);
  const auto key = std::make_tuple(radius, options.eps1, options.levels, options.k, static_cast<int>(options.filter),
                                   options.overlap);
  auto& slot = levels_[key];
  if (slot) return Entry{slot.get(), false};
  for (const auto& chain : chains_) {
    if (chain->filter != options.filter) continue;
    // A chain of another eps_1 (not eps_1 3^-j) or too few levels cannot serve: try the next.
    Result<raster::LodScene> lod = raster::assemble_lod(*scene_, *chain, radius, options);
    if (lod) {
      slot = std::make_unique<raster::LodScene>(std::move(*lod));
      return Entry{slot.get(), true};
    }
  }
  // Three levels to spare: they are small, and let eps_1 3 and 9 and 27 reuse the chain.
  constexpr int kSpare = 3;
  Result<raster::LodChain> chain =
      raster::build_lod_chain(*scene_, options.eps1, options.levels + kSpare, options.filter, progress);
  if (!chain) {
    levels_.erase(key);
    return std::unexpected(chain.error());
  }
  chains_.push_back(std::make_unique<raster::LodChain>(std::move(*chain)));
  Result<raster::LodScene> lod = raster::assemble_lod(*scene_, *chains_.back(), radius, options);
  if (!lod) {
    levels_.erase(key);
    return std::unexpected(lod.error());
  }
  slot = std::make_unique<raster::LodScene>(std::move(*lod));
  return Entry{slot.get(), true};
}

}  // namespace exao::engine
