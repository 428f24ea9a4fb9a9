#pragma once
// The results of `exao bench`: a table on stdout, JSON for scripts, an SVG chart for people.

#include <cstddef>
#include <string>
#include <vector>

#include "engine/engine.h"
#include "core/error.h"

namespace exao::cli {

struct BenchRun {
  int samples = 0;
  float radius = 0.0f;
  std::string radius_text;
  std::string method;
  std::string masks;
  std::string isa;  // the mask kernels' instruction set ("" for embree)
  double seconds = 0.0;
  double mrays_per_s = 0.0;
  double speedup_vs_embree = 0.0;
  double ray_agreement = 0.0;       // share of rays whose blocked bit equals Embree's
  double identical_receivers = 0.0; // share of receivers whose AO equals Embree's
  double mean_abs_error = 0.0;      // |AO - AO_embree|
  double max_abs_error = 0.0;
  double bias = 0.0;                // mean AO - AO_embree (> 0: brighter)
  double identical_8bit = 0.0;      // share of receivers whose 8-bit AO equals Embree's
  // raster+lod only: the levels' eps_1 and build time (not in `seconds`), and the error and
  // speed-up against raster without LOD on the same masks (LOD's own error).
  double lod_eps1 = 0.0;
  int lod_levels = 0;
  double lod_k = 0.0;
  double lod_build_seconds = 0.0;
  double lod_speedup_vs_raster = 0.0;
  double lod_mean_abs_vs_raster = 0.0, lod_max_abs_vs_raster = 0.0, lod_bias_vs_raster = 0.0, lod_identical_8bit_vs_raster = 0.0;
  engine::Stats stats;
};

struct BenchReport {
  std::string label;      // what the receivers are, for tables: "Conference pixels 256x192"
  std::string scene;
  std::size_t triangles = 0;
  std::size_t receivers = 0;
  int threads = 0;
  int width = 0;
  int height = 0;
  std::vector<BenchRun> runs;
};

void print_bench_header(const BenchReport& report);
void print_bench_row(const BenchRun& run, bool stats);
[[nodiscard]] Result<void> write_bench_json(const BenchReport& report, const std::string& path);
/// A Markdown table, one row per method that is not the reference: workload, N, r, method,
/// Mrays/s, the ratio to Embree in the same run, and the agreement with Embree.
[[nodiscard]] Result<void> write_bench_markdown(const BenchReport& report, const std::string& path);
[[nodiscard]] Result<void> write_bench_svg(const BenchReport& report, const std::string& path);

}  // namespace exao::cli
