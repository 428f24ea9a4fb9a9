#pragma once
// The flags of `exao compare` and what it writes: the pictures (AO, error heat maps, the contact
// sheet), compare.json, the Markdown table and the lines it prints. The comparison itself is the
// library's (ssao/comparison.h).

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "cli/common_options.h"
#include "core/error.h"
#include "core/shadow_rays.h"
#include "ssao/comparison.h"

namespace exao::cli {

struct CompareCommandOptions {
  SceneOptions scene;
  RayOptions rays;
  CameraOptions camera;
  std::string masks = "lut";
  std::string methods = "all";
  std::string output = "compare";
  int directions = 8;
  int steps = 4;
  double bias = 0.1;
  bool cosine = false;
  std::string angles = "view";
  double thickness = 0.5;
  int sd_samples = 4;
  double sd_alpha = 0.2;
  int blur = 4;
  std::optional<double> stereo;
  std::string key = "pixel";
  double key_cell = 0.25;
  double mv_angle = 45.0;
  bool compress_whole_list = false;
};

/// exact.exr/.png, <method>.exr/.png and <method>-error.png per method, and contact-sheet.png,
/// of the main view, into `dir`.
[[nodiscard]] Result<void> write_compare_pictures(const ssao::Comparison& comparison, const ShadowRays& rays,
                                                  const std::filesystem::path& dir);

/// The Markdown table: the exact row, then one row per method (with --stereo, the E column).
[[nodiscard]] std::string compare_table(const ssao::Comparison& comparison, const ShadowRays& rays);

/// compare.json and compare.md into `dir`. `stereo_ipd`: the stereo HBAO+ rows' eye distance.
[[nodiscard]] Result<void> write_compare_report(const CompareCommandOptions& flags, const ssao::Comparison& comparison,
                                                const ShadowRays& rays, double stereo_ipd,
                                                const std::filesystem::path& dir);

/// What the command prints: the run's line, the table, the variants against their references,
/// the secondary eye, the stereo passes and the stereo pairs.
void print_compare_summary(const CompareCommandOptions& flags, const ssao::Comparison& comparison, const Scene& scene,
                           const ShadowRays& rays, double stereo_ipd);

}  // namespace exao::cli
