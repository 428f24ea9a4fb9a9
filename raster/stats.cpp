#include "raster/stats.h"

#include <cstdio>

namespace exao::raster {

RasterStats& RasterStats::operator+=(const RasterStats& o) {
  receivers += o.receivers;
  triangles += o.triangles;
  prisms += o.prisms;
  billboards += o.billboards;
  boxes += o.boxes;
  volumes_off += o.volumes_off;
  tile_volumes += o.tile_volumes;
  sphere_mask_skipped += o.sphere_mask_skipped;
  masks += o.masks;
  masks_nonempty += o.masks_nonempty;
  fragments += o.fragments;
  depth_passed += o.depth_passed;
  far_depth_passed += o.far_depth_passed;
  sphere_passed += o.sphere_passed;
  facing_passed += o.facing_passed;
  plane_passed += o.plane_passed;
  horizon_passed += o.horizon_passed;
  full_skipped += o.full_skipped;
  return *this;
}

std::string format_stats(const RasterStats& s) {
  std::string out;
  char line[160];
  const auto add = [&](const char* label, std::uint64_t value) {
    std::snprintf(line, sizeof line, "  %-30s %14llu\n", label, static_cast<unsigned long long>(value));
    out += line;
  };
  add("receivers", s.receivers);
  add("triangles", s.triangles);
  add("volumes: prisms", s.prisms);
  add("volumes: billboards", s.billboards);
  add("volumes: boxes", s.boxes);
  add("volumes reaching no receiver", s.volumes_off);
  add("(tile, volume) pairs drawn", s.tile_volumes);
  if (s.depth_passed > 0) {
    out += "  culling tests (paper Table 2): fragments reaching the mask, relative to all tests on\n";
    const double all = s.horizon_passed > 0 ? static_cast<double>(s.horizon_passed) : 1.0;
    const auto row = [&](const char* label, std::uint64_t value) {
      std::snprintf(line, sizeof line, "    %-28s %14llu  %6.2f\n", label, static_cast<unsigned long long>(value),
                    static_cast<double>(value) / all);
      out += line;
    };
    add("far-face fragments", s.fragments);
    row("depth test only", s.depth_passed);
    row("+ 1. far depth", s.far_depth_passed);
    row("+ 2. bounding sphere", s.sphere_passed);
    row("+ 3. triangle facing", s.facing_passed);
    row("+ 4. plane distance", s.plane_passed);
    row("+ 5. hemisphere facing", s.horizon_passed);
    add("skipped: pixel fully occluded", s.full_skipped);
  }
  add("skipped: sphere mask adds no ray", s.sphere_mask_skipped);
  add("masks computed", s.masks);
  add("masks non-empty", s.masks_nonempty);
  return out;
}

}  // namespace exao::raster
