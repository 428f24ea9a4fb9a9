#include "raster/stats.h"

#include <cstdio>
#include <iterator>

namespace exao::raster {
namespace {

// Every counter of RasterStats once, in the order format_stats prints it, with its label: the
// one list that both summing and printing walk, so a new counter cannot be summed but not
// printed (or the reverse). Table 2's lines are printed only when counted (RasterOptions::stats),
// its rows with their share of horizon_passed.
enum class Line { Count, Table2Count, Table2Row };
struct Counter {
  std::uint64_t RasterStats::*value;
  const char* label;
  Line line;
};
constexpr Counter kCounters[] = {
    {&RasterStats::receivers, "receivers", Line::Count},
    {&RasterStats::triangles, "triangles", Line::Count},
    {&RasterStats::prisms, "volumes: prisms", Line::Count},
    {&RasterStats::billboards, "volumes: billboards", Line::Count},
    {&RasterStats::boxes, "volumes: boxes", Line::Count},
    {&RasterStats::volumes_off, "volumes reaching no receiver", Line::Count},
    {&RasterStats::tile_volumes, "(tile, volume) pairs drawn", Line::Count},
    {&RasterStats::fragments, "far-face fragments", Line::Table2Count},
    {&RasterStats::depth_passed, "depth test only", Line::Table2Row},
    {&RasterStats::far_depth_passed, "+ 1. far depth", Line::Table2Row},
    {&RasterStats::sphere_passed, "+ 2. bounding sphere", Line::Table2Row},
    {&RasterStats::facing_passed, "+ 3. triangle facing", Line::Table2Row},
    {&RasterStats::plane_passed, "+ 4. plane distance", Line::Table2Row},
    {&RasterStats::horizon_passed, "+ 5. hemisphere facing", Line::Table2Row},
    {&RasterStats::full_skipped, "skipped: pixel fully occluded", Line::Table2Count},
    {&RasterStats::sphere_mask_skipped, "skipped: sphere mask adds no ray", Line::Count},
    {&RasterStats::masks, "masks computed", Line::Count},
    {&RasterStats::masks_nonempty, "masks non-empty", Line::Count},
};
static_assert(sizeof(RasterStats) == std::size(kCounters) * sizeof(std::uint64_t),
              "every counter of RasterStats is in kCounters");

}  // namespace

RasterStats& RasterStats::operator+=(const RasterStats& o) {
  for (const Counter& c : kCounters) this->*c.value += o.*c.value;
  return *this;
}

std::string format_stats(const RasterStats& s) {
  const bool table2 = s.depth_passed > 0;
  const double all = s.horizon_passed > 0 ? static_cast<double>(s.horizon_passed) : 1.0;
  std::string out;
  bool table2_headed = false;
  char line[160];
  for (const Counter& c : kCounters) {
    const auto value = static_cast<unsigned long long>(s.*c.value);
    if (c.line != Line::Count && !table2) continue;
    if (c.line != Line::Count && !table2_headed) {
      out += "  culling tests (paper Table 2): fragments reaching the mask, relative to all tests on\n";
      table2_headed = true;
    }
    if (c.line == Line::Table2Row) {
      std::snprintf(line, sizeof line, "    %-28s %14llu  %6.2f\n", c.label, value, static_cast<double>(value) / all);
    } else {
      std::snprintf(line, sizeof line, "  %-30s %14llu\n", c.label, value);
    }
    out += line;
  }
  return out;
}

}  // namespace exao::raster
