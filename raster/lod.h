#pragma once
// exao::raster::build_lod: the levels of detail of the paper's Sec. 4.3 for the raster backend.
//
// Level 0 is the scene's own triangles, in the scene's order; levels 1..L are simplified copies
// with allowed geometric error eps_i = eps_1 * 3^(i-1) (the paper triples it per level). A
// receiver takes occlusion at distance t along a ray from level 0 for t in [0, k eps_1], from
// level i for t in [k eps_i, k eps_{i+1}]; the last level reaches to r. Each triangle carries its
// level's DistanceRange (raster/distance_range.h); the raster backend builds its influence volume
// with r_max and removes the rays shorter than r_min by one more plane test. Levels whose r_min
// would reach r are not built. LodOptions::overlap lets each level start a little before the
// one below ends.
//
// How a level is made. The triangles are welded (exact duplicate vertices merged) and cut into
// connected components; each component is repaired (CGAL Polygon_mesh_processing::
// repair_polygon_soup) and, if two-sided, oriented (orient_polygon_soup, which also splits
// non-manifold vertices and edges: for two-sided triangles that changes no blocked ray, and the
// error bound below holds for the split surface all the same). A component that is still not a
// manifold surface (in practice: a one-sided component that is not consistently oriented or not
// manifold, since flipping or splitting it would change which rays it blocks) is "kept": it stays
// at full detail, range [0, r], in level 0 only.
// Each of the others becomes a CGAL Surface_mesh, and its level i is its level i-1 simplified by
// Surface_mesh_simplification::edge_collapse (Lindstrom-Turk cost and placement) under a filter
// that bounds the error of every collapse by eps_i - eps_{i-1} with respect to level i-1, so
// level i is within eps_i of level 0 (triangle inequality):
//  - Envelope: Polyhedral_envelope_filter, every new face inside the eps-envelope of level i-1
//    (exact predicates: a true bound for the new faces, one-sided);
//  - BoundedDistance: Bounded_distance_placement, only the new vertex within eps of level i-1
//    (cheaper, weaker: the faces around it are not checked).
// Collapses go on until none is allowed (no target count). Sidedness is kept per triangle.
//
// The answer is no longer the ray tracer's: LOD trades exactness for speed (the paper: "we
// cannot anymore claim that the results are consistent with a ray tracer").

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "core/enum_names.h"
#include "core/error.h"
#include "core/progress.h"
#include "core/scene.h"
#include "lut/triangle_set.h"
#include "raster/distance_range.h"

namespace exao::raster {

enum class LodFilter { Envelope, BoundedDistance };

[[nodiscard]] constexpr auto enum_names(LodFilter) {
  return std::to_array<EnumName<LodFilter>>({{LodFilter::Envelope, "envelope"}, {LodFilter::BoundedDistance, "distance"}});
}

/// "envelope" or "distance"; the error names the option lod_filter.
[[nodiscard]] Result<LodFilter> parse_lod_filter(const std::string& name);
[[nodiscard]] const char* lod_filter_name(LodFilter filter);

struct LodOptions {
  float eps1 = 0.0f;  // allowed error of level 1, world units, > 0 and finite
  int levels = 1;     // L, the simplified levels: 1 .. 8 (1: the best measured, docs/raster-lod.md)
  float k = 3.0f;     // range scale (the paper: 2 to 5), > 0 and finite
  /// Level i >= 1 starts at (k - overlap) eps_i instead of k eps_i, so that it overlaps the level
  /// below by overlap * eps_i: where a surface meets a ray near the boundary at a grazing angle,
  /// the finer level may meet it just beyond the boundary and the coarser one (moved by up to
  /// eps_i) just before it, and without overlap neither would block the ray. Blocking twice
  /// costs nothing (masks are OR-ed). 0 <= overlap < k.
  float overlap = 0.0f;
  LodFilter filter = LodFilter::Envelope;
};

/// One-line error naming the option and its value when an option is out of range.
[[nodiscard]] Result<void> check_lod_options(const LodOptions& options);

/// eps_1 for `radius` (world units) and `footprint`, the world size of a pixel at the receivers'
/// median depth: max(r / (9 k), 2 footprints), so that level 0 serves about the first ninth of
/// the radius and no level simplifies below 2 pixels; then rounded down to a power of 3 (in scene
/// units), so that the simplified levels of one eps_1 serve nearby radii and views too. The
/// rule comes from the measurements in docs/raster-lod.md. All > 0.
[[nodiscard]] float auto_lod_eps(float radius, float footprint, int levels, float k);

struct LodLevel {
  float eps = 0.0f;           // allowed error (0 for level 0)
  DistanceRange range;        // of the level's simplified triangles (level 0: of the simplifiable ones)
  std::size_t triangles = 0;  // in this level
  double seconds = 0.0;       // to build it
};

struct LodScene {
  lut::TriangleSet triangles;          // level 0 (the scene's triangles, in order), then levels 1..L
  std::vector<DistanceRange> ranges;   // per triangle of `triangles`
  std::vector<std::uint8_t> level;     // per triangle: 0 .. L
  std::vector<LodLevel> levels;        // [0]: level 0
  std::size_t components = 0;          // connected components after welding
  std::size_t split_components = 0;    // ... two-sided ones whose non-manifold vertices or edges
                                       //     orient_polygon_soup split (then simplified)
  std::size_t kept_components = 0;     // ... kept at full detail (not simplifiable)
  std::size_t kept_triangles = 0;      // ... their triangles
  double seconds = 0.0;                // the whole build (with the chain's)
  std::vector<std::string> notes;      // one line each, for the user (e.g. the kept components)
};

/// The geometry of levels 1..`levels` for errors eps_1 3^(i-1), independent of r and k: the
/// expensive part, which build_lod does once and assemble_lod reuses (a chain for eps_1 serves
/// every eps_1 3^j, at every radius).
struct LodChain {
  float eps1 = 0.0f;
  LodFilter filter = LodFilter::Envelope;
  std::vector<Scene> levels;            // [i - 1]: level i (vertices, two_sided)
  std::vector<double> level_seconds;    // to build each
  std::vector<std::uint8_t> kept;       // per scene triangle: kept at full detail
  std::size_t components = 0, split_components = 0, kept_components = 0, kept_triangles = 0;
  double seconds = 0.0;                 // the whole chain
  std::vector<std::string> notes;
};

/// Welds, cuts into components, repairs, orients and simplifies `levels` levels (0 .. 16).
[[nodiscard]] Result<LodChain> build_lod_chain(const Scene& scene, float eps1, int levels, LodFilter filter,
                                               const ProgressCallback& progress = {});

/// The LodScene of `chain` for radius `radius` and `options` (options.filter is ignored):
/// options.eps1 must be chain.eps1 times a power of 3, 3^j, and the chain must hold levels
/// j+1 .. j+L' (L' the levels below r), else an error naming lod_eps1 or lod_levels.
[[nodiscard]] Result<LodScene> assemble_lod(const Scene& scene, const LodChain& chain, float radius,
                                            const LodOptions& options);

/// The levels of `scene` for AO radius `radius` (world units, > 0). Fails only on bad options.
/// Components are simplified in parallel (TBB); progress per level. Seconds to minutes for a
/// few hundred thousand triangles: build once per scene and radius.
[[nodiscard]] Result<LodScene> build_lod(const Scene& scene, float radius, const LodOptions& options,
                                         const ProgressCallback& progress = {});

/// Sampled one-sided distance from triangle soup `from` to triangle soup `to` (three vertices per
/// triangle, world units): the largest distance from a sample point of `from` (its vertices, edge
/// midpoints and `samples_per_triangle` stratified points on each triangle) to the nearest point
/// of `to`. The two-sided Hausdorff distance is the larger of both directions. `to` non-empty.
[[nodiscard]] double sampled_distance(std::span<const glm::vec3> from, std::span<const glm::vec3> to,
                                      int samples_per_triangle);

/// The triangles of level `i` of `lod`, three vertices each; level 0 without the kept components
/// when `simplifiable_only`.
[[nodiscard]] std::vector<glm::vec3> level_triangles(const LodScene& lod, int i, bool simplifiable_only);

}  // namespace exao::raster
