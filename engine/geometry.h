#pragma once
// exao::engine::Geometry: a scene prepared once for the backends that will use it: the Embree
// scene (the reference, and primary visibility for pixel receivers), the triangle set every mask
// reads, the BVH, and a copy of the scene for raster. Independent of the rays, so one Geometry
// serves engines of many sample counts, radii and mask modes (exao bench).

#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "bvh/bvh.h"
#include "core/embree_reference.h"
#include "core/error.h"
#include "core/progress.h"
#include "core/scene.h"
#include "engine/lod_cache.h"
#include "engine/options.h"
#include "lut/triangle_set.h"

namespace exao::engine {

struct GeometryOptions {
  Sidedness sidedness = Sidedness::Auto;  // applied to the copy the backends see
  CutoutPolicy cutouts;                   // likewise (core/cutouts.h): the scene's cut-outs under it
  bvh::BvhOptions bvh;
  /// Build the Embree scene even when no method casts rays, for pixel receivers and previews.
  bool embree = false;
  int threads = 0;  // 0: one per core
  /// The builds' progress, (done, total) work units: Embree's, then the BVH's; may be called from any thread.
  ProgressCallback progress;
};

class Geometry {
 public:
  /// Prepares `scene` for every method in `methods`. Fails on an empty scene or an Embree error.
  [[nodiscard]] static Result<std::shared_ptr<const Geometry>> build(const Scene& scene, std::span<const Method> methods,
                                                                      const GeometryOptions& options);
  /// The same geometry from a scene the caller gives away: nothing is copied (the sidedness is
  /// applied in place, the copy raster and pixels keep is this scene, Embree reads its vertices
  /// in place) and each array is freed once no backend reads it (for bvh alone, inside the
  /// BVH build before its leaf blocks), so the scene is not part of the peak memory. The scene
  /// is left empty.
  [[nodiscard]] static Result<std::shared_ptr<const Geometry>> build(Scene&& scene, std::span<const Method> methods,
                                                                      const GeometryOptions& options);

  /// nullptr when not built (no method needed it and options.embree was false).
  [[nodiscard]] const EmbreeScene* embree() const { return embree_.get(); }
  [[nodiscard]] const lut::TriangleSet* triangles() const { return triangles_.get(); }
  [[nodiscard]] const bvh::Bvh* bvh() const { return bvh_.get(); }
  /// The scene as the backends see it (sidedness applied); kept only for raster and pixels.
  [[nodiscard]] const Scene* scene() const { return scene_ ? &*scene_ : nullptr; }
  [[nodiscard]] const Bounds& bounds() const { return bounds_; }
  /// The box of every vertex an occluder has, the ground plane's too (bounds() leaves it out):
  /// no segment from p' reaches geometry farther than the farthest corner of this box.
  [[nodiscard]] const Bounds& occluder_bounds() const { return occluder_bounds_; }
  [[nodiscard]] std::size_t triangle_count() const { return triangle_count_; }
  [[nodiscard]] std::size_t two_sided_count() const { return two_sided_count_; }
  [[nodiscard]] Sidedness sidedness() const { return sidedness_; }
  /// Whether any triangle is alpha-tested (a cut-out) under GeometryOptions::cutouts.
  [[nodiscard]] bool has_cutouts() const { return has_cutouts_; }
  [[nodiscard]] const bvh::BvhOptions& bvh_options() const { return bvh_options_; }
  /// The raster method's levels of detail of scene(), built on first use (nullptr when raster
  /// was not prepared). Not const: a memo that every engine over this geometry shares.
  [[nodiscard]] LodCache* lod_cache() const { return lod_cache_.get(); }
  /// Whether this geometry has what `method` needs.
  [[nodiscard]] bool serves(Method method) const;

  /// Refit after a deformation: every triangle of the scene build was given (same count and
  /// order; sidedness and objects kept) moved to `vertices`, 3 per triangle. Embree refits its
  /// BVH, the triangle sets and spheres are recomputed, the BVH keeps its topology with new
  /// boxes and spheres (bvh::Bvh::refit), the bounds follow, and the raster levels of detail
  /// are dropped (built again on first use). Masks and rays then equal a fresh build's bit for
  /// bit. Not while any engine over this geometry runs a query. Errors: a count that does not
  /// match; Embree's.
  [[nodiscard]] Result<void> refit(std::span<const glm::vec3> vertices);

 private:
  [[nodiscard]] static Result<std::shared_ptr<const Geometry>> build_from(const Scene& scene, Scene* owned,
                                                                           std::span<const Method> methods,
                                                                           const GeometryOptions& options);

  // The arrays Embree may read in place come first, so that they outlive it.
  std::optional<Scene> scene_;
  std::vector<glm::vec3> embree_vertices_;  // the vertices Embree reads when no scene_ is kept (else empty)
  std::unique_ptr<EmbreeScene> embree_;
  std::unique_ptr<lut::TriangleSet> triangles_;
  std::unique_ptr<bvh::Bvh> bvh_;
  Bounds bounds_;
  Bounds occluder_bounds_;
  std::size_t ground_triangles_ = 0;  // the scene's last ones, left out of bounds_
  std::size_t triangle_count_ = 0;
  std::size_t two_sided_count_ = 0;
  Sidedness sidedness_ = Sidedness::Auto;
  bool has_cutouts_ = false;
  bvh::BvhOptions bvh_options_;
  std::unique_ptr<LodCache> lod_cache_;
};

}  // namespace exao::engine
