#pragma once
// The results of `exao bench` (bench/report.h): a table on stdout, JSON for scripts, an SVG chart
// for people.

#include <string>

#include "bench/report.h"
#include "core/error.h"

namespace exao::cli {

void print_bench_header(const bench::Report& report);
void print_bench_row(const bench::Run& run, bool stats);
[[nodiscard]] Result<void> write_bench_json(const bench::Report& report, const std::string& path);
/// A Markdown table, one row per method that is not the reference: workload, N, r, method,
/// Mrays/s, the ratio to Embree in the same run, and the agreement with Embree.
[[nodiscard]] Result<void> write_bench_markdown(const bench::Report& report, const std::string& path);
[[nodiscard]] Result<void> write_bench_svg(const bench::Report& report, const std::string& path);

}  // namespace exao::cli
