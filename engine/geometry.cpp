#include "engine/geometry.h"

#include <algorithm>
#include <string>

#include "core/cutouts.h"

#include <tbb/task_arena.h>

namespace exao::engine {
namespace {

bool uses(std::span<const Method> methods, Method method) {
  return std::find(methods.begin(), methods.end(), method) != methods.end();
}

// What the methods of a geometry need built: raster draws the scene, and pixel receivers read its
// triangles' normals (keep_scene); auto is bvh's traversal with Embree.
struct Backends {
  bool raster = false;
  bool keep_scene = false;
  bool embree = false;
  bool brute = false;
  bool bvh = false;
};

Backends backends_of(std::span<const Method> methods, const GeometryOptions& options) {
  Backends b;
  b.raster = uses(methods, Method::Raster);
  b.keep_scene = b.raster || options.embree;
  b.embree = options.embree || uses(methods, Method::Embree) || uses(methods, Method::Auto);
  b.brute = uses(methods, Method::Brute);
  b.bvh = uses(methods, Method::Bvh) || uses(methods, Method::Auto);
  return b;
}

struct BuiltBackends {
  std::unique_ptr<EmbreeScene> embree;
  std::unique_ptr<bvh::Bvh> bvh;
  std::unique_ptr<lut::TriangleSet> triangles;
};

// The backends' structures over `source`, in a TBB arena of options.threads. Embree reads the
// vertices in place when `shareable` (a scene of ours).
Result<BuiltBackends> build_backends(const Backends& b, const Scene& source, bool shareable, Scene* disposable,
                                     const GeometryOptions& options) {
  BuiltBackends out;
  tbb::task_arena arena(options.threads > 0 ? options.threads : static_cast<int>(tbb::task_arena::automatic));
  Result<void> built;
  arena.execute([&] {
    if (b.embree) {
      Result<EmbreeScene> reference =
          shareable ? EmbreeScene::build_sharing(source, options.progress) : EmbreeScene::build(source, options.progress);
      if (!reference) {
        built = std::unexpected(reference.error());
        return;
      }
      out.embree = std::make_unique<EmbreeScene>(std::move(*reference));
    }
    if (b.bvh) {
      // Straight from the scene: the BVH keeps its own copy in leaf order, so the scene-order
      // set (53 bytes a triangle) is made only for brute and raster, after the tree. A
      // disposable scene that nothing reads afterwards is freed inside the build, before the
      // leaf blocks are made.
      const bool free_inside = disposable && !b.embree && !b.brute && !b.raster;
      Result<bvh::Bvh> tree = free_inside ? bvh::Bvh::build(std::move(*disposable), options.bvh, options.progress)
                                          : bvh::Bvh::build(source, options.bvh, options.progress);
      if (!tree) {
        built = std::unexpected(tree.error());
        return;
      }
      out.bvh = std::make_unique<bvh::Bvh>(std::move(*tree));
    }
    if (b.brute || b.raster) out.triangles = std::make_unique<lut::TriangleSet>(lut::TriangleSet::build(source));
  });
  if (!built) return std::unexpected(built.error());
  return out;
}

}  // namespace

bool Geometry::serves(Method method) const {
  switch (method) {
    case Method::Embree: return embree_ != nullptr;
    case Method::Brute: return triangles_ != nullptr;
    case Method::Bvh: return bvh_ != nullptr;
    case Method::Raster: return triangles_ != nullptr && scene_.has_value();
    case Method::Auto: return bvh_ != nullptr && embree_ != nullptr;
  }
  return false;
}

Result<std::shared_ptr<const Geometry>> Geometry::build(const Scene& scene, std::span<const Method> methods,
                                                         const GeometryOptions& options) {
  return build_from(scene, nullptr, methods, options);
}

Result<std::shared_ptr<const Geometry>> Geometry::build(Scene&& scene, std::span<const Method> methods,
                                                         const GeometryOptions& options) {
  return build_from(scene, &scene, methods, options);
}

// `owned` is `scene` when the caller gave it away (build(Scene&&)), else null: then the
// sidedness and cut-out policy are applied in place, the copy kept for raster and pixels is
// that scene itself, Embree reads its vertex array in place, and every array is freed as soon
// as no backend reads it.
Result<std::shared_ptr<const Geometry>> Geometry::build_from(const Scene& scene, Scene* owned,
                                                              std::span<const Method> methods,
                                                              const GeometryOptions& options) {
  if (auto ok = bvh::check_options(options.bvh); !ok) return std::unexpected(ok.error());
  if (scene.triangle_count() == 0) return fail(scene.name + ": the scene has no triangle of non-zero area");
  auto geometry = std::make_shared<Geometry>();
  const Backends backends = backends_of(methods, options);
  const bool keep_scene = backends.keep_scene;
  // The backends see the scene with the sidedness applied; a copy only when it changes or must
  // be kept (raster draws it, pixel receivers read its triangles' normals) and the caller keeps
  // the original.
  const Scene* source = &scene;
  Scene* disposable = nullptr;  // a scene of ours that no one needs after the build
  if (owned) {
    apply_sidedness(*owned, options.sidedness);
    owned->cutouts = apply_cutout_policy(owned->cutouts, options.cutouts);
    if (keep_scene) {
      geometry->scene_ = std::move(*owned);
      source = &*geometry->scene_;
    } else {
      disposable = owned;
      // No backend reads materials (4 bytes a triangle): gone before the builds' peak.
      disposable->material = {};
    }
  } else if (options.sidedness != Sidedness::Auto || keep_scene || scene.cutouts) {
    geometry->scene_ = scene;
    apply_sidedness(*geometry->scene_, options.sidedness);
    geometry->scene_->cutouts = apply_cutout_policy(scene.cutouts, options.cutouts);
    source = &*geometry->scene_;
    if (!keep_scene) disposable = &*geometry->scene_;
  }
  geometry->has_cutouts_ = source->cutouts != nullptr;
  geometry->bounds_ = source->bounds();
  geometry->ground_triangles_ = source->ground_triangles;
  for (const glm::vec3& v : source->vertices) geometry->occluder_bounds_.extend(v);
  geometry->triangle_count_ = source->triangle_count();
  geometry->two_sided_count_ = exao::two_sided_count(*source);
  geometry->sidedness_ = options.sidedness;
  geometry->bvh_options_ = options.bvh;

  // Embree reads the vertices of a scene of ours in place: the kept copy's, or the disposable
  // one's, which are then moved (not copied) to embree_vertices_.
  Scene* shareable = keep_scene ? &*geometry->scene_ : disposable;
  if (backends.embree && shareable) {
    std::vector<glm::vec3>& vertices = shareable->vertices;
    if (vertices.capacity() < vertices.size() + Scene::kVertexPadding) vertices.reserve(vertices.size() + Scene::kVertexPadding);
  }
  Result<BuiltBackends> built = build_backends(backends, *source, shareable != nullptr, disposable, options);
  if (!built) return std::unexpected(built.error());
  geometry->embree_ = std::move(built->embree);
  geometry->bvh_ = std::move(built->bvh);
  geometry->triangles_ = std::move(built->triangles);
  if (disposable) {
    if (geometry->embree_ && geometry->embree_->shares_vertices()) geometry->embree_vertices_ = std::move(disposable->vertices);
    *disposable = Scene{};
  }
  if (!keep_scene) geometry->scene_.reset();
  if (backends.raster) geometry->lod_cache_ = std::make_unique<LodCache>(*geometry->scene_);
  return std::shared_ptr<const Geometry>(std::move(geometry));
}

Result<void> Geometry::refit(std::span<const glm::vec3> vertices) {
  if (vertices.size() != 3 * triangle_count_) {
    return fail("refit: " + std::to_string(vertices.size()) + " vertices for " + std::to_string(triangle_count_) +
                " triangles (3 each)");
  }
  // The arrays Embree may read in place first (same size: no reallocation), then Embree.
  if (scene_) {
    scene_->vertices.assign(vertices.begin(), vertices.end());
    if (lod_cache_) lod_cache_ = std::make_unique<LodCache>(*scene_);
  }
  if (!embree_vertices_.empty()) embree_vertices_.assign(vertices.begin(), vertices.end());
  if (embree_) {
    const std::vector<glm::vec3>& shared = scene_ ? scene_->vertices : embree_vertices_;
    if (auto ok = embree_->refit(embree_->shares_vertices() ? std::span<const glm::vec3>(shared) : vertices); !ok) {
      return ok;
    }
  }
  if (triangles_) triangles_->set_vertices(vertices);
  if (bvh_) {
    bvh_->refit(vertices);  // its leaf blocks keep sidedness and cut-outs, the tree its objects
  }
  bounds_ = Bounds{};
  occluder_bounds_ = Bounds{};
  const std::size_t model = 3 * (triangle_count_ - std::min(ground_triangles_, triangle_count_));
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    if (i < model) bounds_.extend(vertices[i]);
    occluder_bounds_.extend(vertices[i]);
  }
  return {};
}

}  // namespace exao::engine
