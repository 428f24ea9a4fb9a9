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
  add_lod_level_options(app, options);
}

void add_lod_level_options(CLI::App& app, LodCliOptions& options) {
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

Result<std::optional<raster::LodOptions>> parse_lod(const LodCliOptions& options) {
  raster::LodOptions out;
  Result<raster::LodFilter> filter = raster::parse_lod_filter(options.filter);
  if (!filter) return std::unexpected(filter.error());
  out.levels = options.levels;
  out.k = options.k;
  out.overlap = options.overlap;
  out.filter = *filter;
  if (options.lod == "off") return std::optional<raster::LodOptions>{};
  if (options.lod == "auto") {
    out.eps1 = 0.0f;  // the engine resolves it from r and the pixel footprint
    return std::optional<raster::LodOptions>{out};
  }
  std::size_t used = 0;
  float eps = 0.0f;
  try {
    eps = std::stof(options.lod, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  // 0 would read as auto: refused here with the rest.
  if (used == 0 || used != options.lod.size() || !(eps > 0.0f) || !std::isfinite(eps)) {
    return fail("lod_eps1: expected off, auto or a positive length, got '" + options.lod + "'");
  }
  out.eps1 = eps;
  return std::optional<raster::LodOptions>{out};
}

std::string describe_lod(const engine::LodLevels& levels) {
  const raster::LodScene& lod = *levels.levels;
  const raster::LodOptions& options = levels.options;
  char line[256];
  std::snprintf(line, sizeof line, "lod: eps_1 = %g%s, k = %g, %s filter, built in %.2f s:", double(options.eps1),
                levels.automatic ? " (auto)" : "", double(options.k), raster::lod_filter_name(options.filter), lod.seconds);
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
