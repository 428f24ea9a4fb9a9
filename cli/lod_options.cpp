#include "cli/lod_options.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

namespace exao::cli {

void add_lod_options(CLI::App& app, LodCliOptions& options) {
  app.add_option("--lod", options.lod,
                 "raster: level of detail (paper Sec. 4.3): off, auto (eps_1 from r and the pixel size) or eps_1, "
                 "the first level's allowed error (world units)")
      ->capture_default_str();
  app.add_option("--lod-levels", options.levels, "raster: simplified levels L, 1 to 8 (eps_i = eps_1 3^(i-1))")
      ->capture_default_str();
  app.add_option("--lod-k", options.k, "raster: level i serves distances [k eps_i, k eps_(i+1)]; > 0 (paper: 2 to 5)")
      ->capture_default_str();
  app.add_option("--lod-overlap", options.overlap,
                 "raster: level i starts at (k - overlap) eps_i, overlapping the level below; 0 to k")
      ->capture_default_str();
  app.add_option("--lod-filter", options.filter,
                 "raster: error bound of each collapse: envelope (Polyhedral_envelope_filter) or distance "
                 "(Bounded_distance_placement)")
      ->capture_default_str();
}

Result<std::optional<raster::LodOptions>> check_lod_cli(const LodCliOptions& options) {
  raster::LodOptions out;
  if (options.levels < 1 || options.levels > 8) {
    return fail("--lod-levels: must be 1 to 8, not " + std::to_string(options.levels));
  }
  if (!(options.k > 0.0f) || !std::isfinite(options.k)) return fail("--lod-k: must be a positive number");
  if (!(options.overlap >= 0.0f) || !(options.overlap < options.k)) {
    return fail("--lod-overlap: must be at least 0 and less than --lod-k");
  }
  Result<raster::LodFilter> filter = raster::parse_lod_filter(options.filter);
  if (!filter) return fail("--lod-filter: unknown filter '" + options.filter + "' (envelope or distance)");
  out.levels = options.levels;
  out.k = options.k;
  out.overlap = options.overlap;
  out.filter = *filter;
  if (options.lod == "off") return std::optional<raster::LodOptions>{};
  if (options.lod == "auto") {
    out.eps1 = 0.0f;  // resolved later from r and the pixel footprint
    return std::optional<raster::LodOptions>{out};
  }
  std::size_t used = 0;
  float eps = 0.0f;
  try {
    eps = std::stof(options.lod, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != options.lod.size() || !(eps > 0.0f) || !std::isfinite(eps)) {
    return fail("--lod: expected off, auto or a positive length, not '" + options.lod + "'");
  }
  out.eps1 = eps;
  return std::optional<raster::LodOptions>{out};
}

float pixel_footprint(const PixelReceivers& pixels, const Camera& camera) {
  if (pixels.receivers.empty() || pixels.height <= 0) return 0.0f;
  std::vector<float> depth;
  depth.reserve(pixels.receivers.size());
  for (const Receiver& r : pixels.receivers) depth.push_back(glm::dot(r.position - camera.eye, camera.forward));
  auto middle = depth.begin() + static_cast<std::ptrdiff_t>(depth.size() / 2);
  std::nth_element(depth.begin(), middle, depth.end());
  return *middle * 2.0f * std::tan(0.5f * camera.yfov) / static_cast<float>(pixels.height);
}

raster::LodOptions resolve_lod(const raster::LodOptions& checked, bool automatic, float radius, float footprint) {
  raster::LodOptions out = checked;
  if (automatic) out.eps1 = raster::auto_lod_eps(radius, footprint, checked.levels, checked.k);
  return out;
}

const raster::LodScene& LodCache::get(float radius, const raster::LodOptions& options, const ProgressCallback& progress,
                                      bool* built) {
  const auto key = std::make_tuple(radius, options.eps1, options.levels, options.k, static_cast<int>(options.filter),
                                   options.overlap);
  auto& slot = levels_[key];
  if (built) *built = !slot;
  if (slot) return *slot;
  // The options were checked by check_lod_cli and resolve_lod: the library cannot refuse them.
  for (const auto& chain : chains_) {
    if (chain->filter != options.filter) continue;
    Result<raster::LodScene> lod = raster::assemble_lod(*scene_, *chain, radius, options);
    if (lod) {
      slot = std::make_unique<raster::LodScene>(std::move(*lod));
      return *slot;
    }
  }
  // Three levels to spare: they are small, and let eps_1 3 and 9 and 27 reuse the chain.
  constexpr int kSpare = 3;
  Result<raster::LodChain> chain = raster::build_lod_chain(*scene_, options.eps1, options.levels + kSpare, options.filter, progress);
  chains_.push_back(std::make_unique<raster::LodChain>(std::move(*chain)));
  Result<raster::LodScene> lod = raster::assemble_lod(*scene_, *chains_.back(), radius, options);
  slot = std::make_unique<raster::LodScene>(std::move(*lod));
  return *slot;
}

MaskSet run_raster_lod(const Scene& scene, const raster::LodScene& lod, const lut::MaskEngine& engine,
                       const PixelReceivers& pixels, const Camera& camera, raster::RasterOptions options,
                       const ProgressCallback& progress, raster::RasterStats* stats) {
  options.ranges = lod.ranges;
  options.stats = stats != nullptr;
  raster::RasterResult result = raster::occlusion(pixels, scene, lod.triangles, engine, camera, options, progress);
  if (stats) *stats = result.stats;
  return std::move(result.masks);
}

AoError ao_error(const MaskSet& reference, const MaskSet& masks) {
  AoError e;
  const std::size_t n = reference.size();
  if (n == 0) return e;
  // The rounding of core/image_io's PNG writer.
  const auto quantise = [](float ao) { return std::lround(std::clamp(ao, 0.0f, 1.0f) * 255.0f); };
  double sum_abs = 0.0, sum = 0.0;
  std::size_t same = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const float a = reference.ao(i), b = masks.ao(i);
    const double d = double(b) - double(a);
    sum += d;
    sum_abs += std::abs(d);
    e.max_abs = std::max(e.max_abs, std::abs(d));
    same += quantise(a) == quantise(b);
  }
  e.mean_abs = sum_abs / double(n);
  e.bias = sum / double(n);
  e.identical_8bit = double(same) / double(n);
  return e;
}

std::string describe_lod(const raster::LodScene& lod, const raster::LodOptions& options, bool automatic) {
  char line[256];
  std::snprintf(line, sizeof line, "lod: eps_1 = %g%s, k = %g, %s filter, built in %.2f s:", double(options.eps1),
                automatic ? " (auto)" : "", double(options.k), raster::lod_filter_name(options.filter), lod.seconds);
  std::string out = line;
  for (std::size_t i = 0; i < lod.levels.size(); ++i) {
    const raster::LodLevel& l = lod.levels[i];
    std::snprintf(line, sizeof line, " L%zu [%g, %g] %zu tris;", i, double(l.range.r_min), double(l.range.r_max),
                  l.triangles);
    out += line;
  }
  out.pop_back();
  for (const std::string& note : lod.notes) out += "\nlod: " + note;
  return out;
}

}  // namespace exao::cli
