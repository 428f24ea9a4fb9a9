#include "cli/bench_report.h"

#include <algorithm>
#include <cstdio>
#include <map>
#include <sstream>

#include <nlohmann/json.hpp>

#include "bvh/traverse.h"
#include "core/atomic_write.h"
#include "core/isa.h"

namespace exao::cli {
namespace {

std::string escape_xml(const std::string& s) {
  std::string out;
  for (const char c : s) {
    if (c == '<') out += "&lt;";
    else if (c == '>') out += "&gt;";
    else if (c == '&') out += "&amp;";
    else out += c;
  }
  return out;
}

// The chart's group of a row (one per N and radius) and its series (one per method and mask mode).
std::string bar_group(const bench::Run& run) { return "N=" + std::to_string(run.samples) + ", r=" + run.radius_text; }
std::string bar_series(const bench::Run& run) { return run.method + (run.method == "embree" ? "" : " (" + run.masks + ")"); }

}  // namespace

void print_bench_header(const bench::Report& report) {
  std::printf("scene %s: %zu triangles, %dx%d camera, %zu receivers, %d threads\n", report.scene.c_str(),
              report.triangles, report.width, report.height, report.receivers, report.threads);
  std::printf("%5s %10s %-10s %-8s %-6s %9s %9s %8s %10s %9s %9s %9s\n", "N", "radius", "method", "masks", "isa", "seconds",
              "Mrays/s", "x embree", "rays agree", "identical", "mean|dAO|", "max|dAO|");
}

void print_bench_row(const bench::Run& run, bool stats) {
  std::printf("%5d %10.4g %-10s %-8s %-6s %9.3f %9.1f %8.2f %9.4f%% %8.2f%% %9.5f %9.5f\n", run.samples,
              static_cast<double>(run.radius), run.method.c_str(), run.masks.c_str(), run.isa.c_str(), run.seconds, run.mrays_per_s,
              run.speedup_vs_embree, 100.0 * run.ray_agreement, 100.0 * run.identical_receivers, run.mean_abs_error,
              run.max_abs_error);
  if (run.lod_build_seconds > 0.0) {
    std::printf("      lod eps_1 %g (levels built in %.2f s, not counted): %.2fx raster; against raster: mean|dAO| %.5f, "
                "max|dAO| %.5f, bias %+.5f, 8-bit identical %.2f%%; against embree: bias %+.5f, 8-bit identical %.2f%%\n",
                run.lod_eps1, run.lod_build_seconds, run.lod_speedup_vs_raster, run.lod_mean_abs_vs_raster,
                run.lod_max_abs_vs_raster, run.lod_bias_vs_raster, 100.0 * run.lod_identical_8bit_vs_raster, run.bias,
                100.0 * run.identical_8bit);
  }
  if (stats && run.stats.raster.receivers) std::printf("%s", raster::format_stats(run.stats.raster).c_str());
  if (stats && run.stats.traversal.receivers) {
    const Result<std::optional<Isa>> isa = parse_isa(run.isa);
    std::printf("      %s", bvh::format_stats(run.stats.traversal, isa && *isa ? **isa : default_isa()).c_str());
  }
  std::fflush(stdout);
}

Result<void> write_bench_json(const bench::Report& report, const std::string& path) {
  nlohmann::json j;
  j["label"] = report.label;
  j["scene"] = report.scene;
  j["triangles"] = report.triangles;
  j["receivers"] = report.receivers;
  j["threads"] = report.threads;
  j["width"] = report.width;
  j["height"] = report.height;
  j["runs"] = nlohmann::json::array();
  for (const bench::Run& run : report.runs) {
    nlohmann::json r{{"samples", run.samples},
                     {"radius", run.radius},
                     {"radius_option", run.radius_text},
                     {"method", run.method},
                     {"masks", run.masks},
                     {"isa", run.isa},
                     {"seconds", run.seconds},
                     {"mrays_per_s", run.mrays_per_s},
                     {"speedup_vs_embree", run.speedup_vs_embree},
                     {"ray_agreement", run.ray_agreement},
                     {"identical_receivers", run.identical_receivers},
                     {"mean_abs_error", run.mean_abs_error},
                     {"max_abs_error", run.max_abs_error},
                     {"bias", run.bias},
                     {"identical_8bit", run.identical_8bit}};
    if (run.lod_build_seconds > 0.0) {
      r["lod_eps1"] = run.lod_eps1;
      r["lod_levels"] = run.lod_levels;
      r["lod_k"] = run.lod_k;
      r["lod_build_seconds"] = run.lod_build_seconds;
      r["lod_speedup_vs_raster"] = run.lod_speedup_vs_raster;
      r["lod_mean_abs_vs_raster"] = run.lod_mean_abs_vs_raster;
      r["lod_max_abs_vs_raster"] = run.lod_max_abs_vs_raster;
      r["lod_bias_vs_raster"] = run.lod_bias_vs_raster;
      r["lod_identical_8bit_vs_raster"] = run.lod_identical_8bit_vs_raster;
    }
    const auto& t = run.stats.traversal;
    if (t.receivers) {
      const double n = static_cast<double>(t.receivers);
      r["nodes_visited"] = static_cast<double>(t.nodes_visited) / n;
      r["triangles_tested"] = static_cast<double>(t.triangles_tested) / n;
      r["triangles_blocking"] = static_cast<double>(t.triangles_blocking) / n;
    }
    j["runs"].push_back(r);
  }
  return write_file_atomically(path, j.dump(2) + "\n");
}

// Groups of bars, one group per (N, radius), one bar per method and mask mode, height Mrays/s.
Result<void> write_bench_markdown(const bench::Report& report, const std::string& path) {
  std::ostringstream md;
  md << "| workload | N | r | method | Mrays/s | x embree | rays agreeing | receivers identical |\n"
     << "|---|---|---|---|---|---|---|---|\n";
  char line[512];
  for (const bench::Run& run : report.runs) {
    if (run.method == "embree" && run.speedup_vs_embree == 1.0) {
      std::snprintf(line, sizeof line, "| %s | %d | %s | embree %s | %.1f | 1.00 | | |\n", report.label.c_str(),
                    run.samples, run.radius_text.c_str(), run.masks.c_str(), run.mrays_per_s);
    } else {
      std::snprintf(line, sizeof line, "| %s | %d | %s | %s %s %s | %.1f | **%.2f** | %.4f%% | %.2f%% |\n",
                    report.label.c_str(), run.samples, run.radius_text.c_str(), run.method.c_str(), run.masks.c_str(),
                    run.isa.c_str(), run.mrays_per_s, run.speedup_vs_embree, 100.0 * run.ray_agreement,
                    100.0 * run.identical_receivers);
    }
    md << line;
  }
  return write_file_atomically(path, md.str());
}

Result<void> write_bench_svg(const bench::Report& report, const std::string& path) {
  std::vector<std::string> groups, series;
  for (const bench::Run& run : report.runs) {
    const std::string g = bar_group(run), s = bar_series(run);
    if (std::find(groups.begin(), groups.end(), g) == groups.end()) groups.push_back(g);
    if (std::find(series.begin(), series.end(), s) == series.end()) series.push_back(s);
  }
  double top = 1.0;
  for (const bench::Run& run : report.runs) top = std::max(top, run.mrays_per_s);
  const char* colours[] = {"#888888", "#d95f02", "#1b9e77", "#7570b3", "#e7298a", "#66a61e"};
  const int bar = 28, gap = 24, left = 60, plot_h = 300, base = 40 + plot_h;
  const int group_w = static_cast<int>(series.size()) * bar + gap;
  const int width = left + static_cast<int>(groups.size()) * group_w + 200;
  std::ostringstream svg;
  svg << "<svg xmlns='http://www.w3.org/2000/svg' width='" << width << "' height='" << base + 60
      << "' font-family='sans-serif' font-size='12'>\n<rect width='100%' height='100%' fill='white'/>\n";
  svg << "<text x='" << left << "' y='20' font-size='14'>" << escape_xml(report.scene) << ": Mrays/s, "
      << report.receivers << " receivers, " << report.threads << " threads</text>\n";
  for (int tick = 0; tick <= 4; ++tick) {
    const double value = top * tick / 4.0;
    const int y = base - static_cast<int>(plot_h * tick / 4.0);
    svg << "<line x1='" << left << "' x2='" << width - 200 << "' y1='" << y << "' y2='" << y << "' stroke='#ddd'/>"
        << "<text x='" << left - 6 << "' y='" << y + 4 << "' text-anchor='end'>" << static_cast<int>(value) << "</text>\n";
  }
  for (const bench::Run& run : report.runs) {
    const std::string g = bar_group(run), s = bar_series(run);
    const auto gi = std::find(groups.begin(), groups.end(), g) - groups.begin();
    const auto si = std::find(series.begin(), series.end(), s) - series.begin();
    const int h = static_cast<int>(plot_h * run.mrays_per_s / top);
    const int x = left + static_cast<int>(gi) * group_w + static_cast<int>(si) * bar;
    svg << "<rect x='" << x << "' y='" << base - h << "' width='" << bar - 4 << "' height='" << h << "' fill='"
        << colours[si % 6] << "'><title>" << escape_xml(s) << ": " << run.mrays_per_s << " Mrays/s</title></rect>\n";
  }
  for (std::size_t gi = 0; gi < groups.size(); ++gi) {
    svg << "<text x='" << left + static_cast<int>(gi) * group_w + (group_w - gap) / 2 << "' y='" << base + 18
        << "' text-anchor='middle'>" << escape_xml(groups[gi]) << "</text>\n";
  }
  for (std::size_t si = 0; si < series.size(); ++si) {
    const int y = 50 + static_cast<int>(si) * 18;
    svg << "<rect x='" << width - 190 << "' y='" << y - 10 << "' width='12' height='12' fill='" << colours[si % 6]
        << "'/><text x='" << width - 172 << "' y='" << y << "'>" << escape_xml(series[si]) << "</text>\n";
  }
  svg << "</svg>\n";
  return write_file_atomically(path, svg.str());
}

}  // namespace exao::cli
