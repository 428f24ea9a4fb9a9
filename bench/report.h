#pragma once
// exao::bench::Run and Report: what one timed row of `exao bench` measured (its time, its speed,
// and how its masks agree with Embree's on the same rays), and the workload the rows share.
// Plain values: the exao program prints them as a table, JSON, Markdown and SVG (cli/bench_report.h).

#include <cstddef>
#include <string>
#include <vector>

#include "engine/engine.h"

namespace exao::bench {

struct Run {
  int samples = 0;
  float radius = 0.0f;        // world units, resolved for the scene
  std::string radius_text;    // the radius as the plan gave it ("1%", "0.5")
  std::string method;         // engine::method_name, or "raster+lod"
  std::string masks;          // the mask mode's name, or Embree's ray mode for embree
  std::string isa;            // the mask kernels' instruction set ("" for embree)
  double seconds = 0.0;       // the fastest of the plan's repeats
  double mrays_per_s = 0.0;   // receivers x N / seconds, in millions
  double speedup_vs_embree = 0.0;   // the first (reference) row's seconds / seconds
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
  engine::Stats stats;  // the backend's counters of the first repeat, when the plan asks for them
};

struct Report {
  std::string label;      // what the receivers are, for tables: "Conference pixels 256x192"
  std::string scene;
  std::size_t triangles = 0;
  std::size_t receivers = 0;
  int threads = 0;
  int width = 0;          // the receivers as an image: the camera's size, or (count, 1) for a bake's
  int height = 0;
  std::vector<Run> runs;  // in the order they ran: per (N, r), the reference row first
};

}  // namespace exao::bench
