#include "bvh/traverse.h"

#include <cstdio>

namespace exao::bvh {

const TraverseTable& traverse_table(Isa isa) {
  switch (isa) {
    case Isa::Scalar: return scalar_lanes::traverse_table();
    case Isa::Sse2: return sse2::traverse_table();
    case Isa::Sse4: return sse4::traverse_table();
    case Isa::Avx2: return avx2::traverse_table();
    case Isa::Avx512: return avx512::traverse_table();
  }
  return scalar_lanes::traverse_table();
}

std::string format_stats(const TraversalStats& t, Isa isa) {
  if (t.receivers == 0) return {};
  const double n = static_cast<double>(t.receivers);
  const double vectors = static_cast<double>(t.kernels.cluster_tests) * kSampleCluster / isa_lanes(isa);
  char line[320];
  std::snprintf(line, sizeof line,
                "per receiver: %.1f nodes visited, %.1f triangles tested (%.1f blocked a new ray) + %.1f cached "
                "occluders, %.1f plane tests, %.1f sphere masks, %.1f %s vectors + %.1f single samples; %llu bits outside their clip spheres\n",
                static_cast<double>(t.nodes_visited) / n, static_cast<double>(t.triangles_tested) / n,
                static_cast<double>(t.triangles_blocking) / n, static_cast<double>(t.triangles_cached) / n, static_cast<double>(t.kernels.triangle_masks) / n,
                static_cast<double>(t.kernels.sphere_masks) / n, vectors / n, isa_name(isa),
                static_cast<double>(t.kernels.near_samples) / n, static_cast<unsigned long long>(t.kernels.clip_removed));
  std::string out = line;
  if (t.rays > 0) {
    std::snprintf(line, sizeof line,
                  "auto: %.2f%% of rays decided by masks, %.2f%% cast with Embree; masks stopped by the cost model on "
                  "%.1f%% of receivers\n",
                  100.0 * static_cast<double>(t.rays - t.rays_cast) / static_cast<double>(t.rays),
                  100.0 * static_cast<double>(t.rays_cast) / static_cast<double>(t.rays),
                  100.0 * static_cast<double>(t.receivers_stopped) / n);
    out += line;
  }
  return out;
}

}  // namespace exao::bvh
