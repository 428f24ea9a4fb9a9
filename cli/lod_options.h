#pragma once
// The raster backend's level of detail on the command line (paper Sec. 4.3, raster/lod.h):
// --lod auto|off|EPS1, --lod-levels L, --lod-k K, --lod-overlap O, --lod-filter envelope|distance,
// parsed into engine::Options::lod (the engine checks the values, builds the levels and keeps
// them, engine/lod_cache.h), and the lines that report them.

#include <optional>
#include <string>

#include <CLI/CLI.hpp>

#include "core/error.h"
#include "engine/engine.h"
#include "raster/lod.h"

namespace exao::cli {

struct LodCliOptions {
  std::string lod = "off";  // off | auto | a length (eps_1, world units)
  int levels = 1;
  float k = 3.0f;
  float overlap = 0.0f;
  std::string filter = "envelope";
};

void add_lod_options(CLI::App& app, LodCliOptions& options);
/// The levels' shape alone (--lod-levels, --lod-k, --lod-overlap, --lod-filter): part of
/// add_lod_options; `exao bench` takes its own list of --lod values.
void add_lod_level_options(CLI::App& app, LodCliOptions& options);

/// engine::Options::lod from the flags: nullopt for --lod off, eps1 0 for auto. Syntax only (the
/// engine checks the ranges); errors name the option (lod_eps1, lod_filter), which report() prints
/// as its flag.
[[nodiscard]] Result<std::optional<raster::LodOptions>> parse_lod(const LodCliOptions& options);

/// One line describing the levels: eps, ranges, triangle counts, build time.
[[nodiscard]] std::string describe_lod(const engine::LodLevels& lod);

}  // namespace exao::cli
