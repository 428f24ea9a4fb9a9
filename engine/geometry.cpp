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
  if (auto ok = bvh::check_options(options.bvh); !ok) return std::unexpected(ok.error());
  if (scene.triangle_count() == 0) return fail(scene.name + ": the scene has no triangle of non-zero area");
  auto geometry = std::make_shared<Geometry>();
  const bool raster = uses(methods, Method::Raster);
  const bool keep_scene = raster || options.embree;
  // The backends see the scene with the sidedness applied; a copy only when it changes or must
  // be kept (raster draws it, pixel receivers read its triangles' normals).
  const Scene* source = &scene;
  if (options.sidedness != Sidedness::Auto || keep_scene || scene.cutouts) {
    geometry->scene_ = scene;
    apply_sidedness(*geometry->scene_, options.sidedness);
    geometry->scene_->cutouts = apply_cutout_policy(scene.cutouts, options.cutouts);
    source = &*geometry->scene_;
  }
  geometry->has_cutouts_ = source->cutouts != nullptr;
  geometry->bounds_ = source->bounds();
  geometry->ground_triangles_ = source->ground_triangles;
  for (const glm::vec3& v : source->vertices) geometry->occluder_bounds_.extend(v);
  geometry->triangle_count_ = source->triangle_count();
  geometry->two_sided_count_ = exao::two_sided_count(*source);
  geometry->sidedness_ = options.sidedness;
  geometry->bvh_options_ = options.bvh;

  tbb::task_arena arena(options.threads > 0 ? options.threads : static_cast<int>(tbb::task_arena::automatic));
  Result<void> built;
  arena.execute([&] {
    if (options.embree || uses(methods, Method::Embree) || uses(methods, Method::Auto)) {
      Result<EmbreeScene> embree = EmbreeScene::build(*source);
      if (!embree) {
        built = std::unexpected(embree.error());
        return;
      }
      geometry->embree_ = std::make_unique<EmbreeScene>(std::move(*embree));
    }
    const bool brute = uses(methods, Method::Brute);
    const bool bvh = uses(methods, Method::Bvh) || uses(methods, Method::Auto);
    if (bvh) {
      // Straight from the scene: the BVH keeps its own copy in leaf order, so the scene-order
      // set (53 bytes a triangle) is made only for brute and raster, after the tree.
      Result<bvh::Bvh> tree = bvh::Bvh::build(*source, options.bvh, options.progress);
      if (!tree) {
        built = std::unexpected(tree.error());
        return;
      }
      geometry->bvh_ = std::make_unique<bvh::Bvh>(std::move(*tree));
    }
    if (brute || raster) geometry->triangles_ = std::make_unique<lut::TriangleSet>(lut::TriangleSet::build(*source));
  });
  if (!built) return std::unexpected(built.error());
  if (!keep_scene) geometry->scene_.reset();
  if (raster) geometry->lod_cache_ = std::make_unique<LodCache>(*geometry->scene_);
  return std::shared_ptr<const Geometry>(std::move(geometry));
}

Result<void> Geometry::refit(std::span<const glm::vec3> vertices) {
  if (vertices.size() != 3 * triangle_count_) {
    return fail("refit: " + std::to_string(vertices.size()) + " vertices for " + std::to_string(triangle_count_) +
                " triangles (3 each)");
  }
  if (embree_) {
    if (auto ok = embree_->refit(vertices); !ok) return ok;
  }
  if (scene_) {
    scene_->vertices.assign(vertices.begin(), vertices.end());
    if (lod_cache_) lod_cache_ = std::make_unique<LodCache>(*scene_);
  }
  if (triangles_) triangles_->set_vertices(vertices);
  if (bvh_) {
    bvh_->refit(vertices);  // its packed triangles keep sidedness, cut-outs and objects
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
