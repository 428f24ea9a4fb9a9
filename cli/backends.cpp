#include "cli/backends.h"

#include "bvh/occlusion.h"
#include "lut/brute.h"

#include <algorithm>

namespace exao::cli {

const char* method_name(Method method) {
  switch (method) {
    case Method::Embree: return "embree";
    case Method::Brute: return "brute";
    case Method::Bvh: return "bvh";
    case Method::Raster: return "raster";
  }
  return "?";
}

std::vector<std::string> method_names() { return {"embree", "brute", "bvh", "raster"}; }

Result<Method> parse_method(const std::string& name) {
  for (const Method m : {Method::Embree, Method::Brute, Method::Bvh, Method::Raster}) {
    if (name == method_name(m)) return m;
  }
  return fail("--method: unknown method '" + name + "' (embree, brute, bvh or raster)");
}

Result<Backends> Backends::prepare(const Scene& scene, std::span<const Method> methods, const BackendOptions& options) {
  Backends b;
  b.scene_ = &scene;
  b.options_ = options;
  Result<EmbreeScene> embree = EmbreeScene::build(scene);
  if (!embree) return std::unexpected(embree.error());
  b.embree_ = std::make_unique<EmbreeScene>(std::move(*embree));
  b.triangles_ = std::make_unique<lut::TriangleSet>(lut::TriangleSet::build(scene));
  if (std::find(methods.begin(), methods.end(), Method::Bvh) != methods.end()) {
    Result<bvh::Bvh> built = bvh::Bvh::build(*b.triangles_, options.bvh);
    if (!built) return std::unexpected(built.error());
    b.bvh_ = std::make_unique<bvh::Bvh>(std::move(*built));
  }
  return b;
}

Result<lut::MaskEngine> Backends::engine(const ShadowRays& rays, lut::MaskMode mode, std::optional<Isa> isa) const {
  return lut::MaskEngine::build(rays, mode, options_.table_resolution, isa ? isa : options_.isa);
}

MaskSet Backends::run(Method method, const ShadowRays& rays, const lut::MaskEngine* engine,
                      std::span<const Receiver> receivers, const ProgressCallback& progress, BackendStats* stats,
                      std::optional<EmbreeRays> embree_rays) const {
  EmbreeOptions embree_options = options_.embree;
  if (embree_rays) embree_options.rays = *embree_rays;
  switch (method) {
    case Method::Embree: return embree_->occlusion(rays, receivers, embree_options, progress);
    case Method::Brute: return lut::brute_occlusion(*engine, *triangles_, receivers, progress);
    case Method::Bvh: return bvh::occlusion(*bvh_, *engine, receivers, progress, stats ? &stats->traversal : nullptr);
    case Method::Raster: break;  // needs a camera: run_raster
  }
  return {};
}

MaskSet Backends::run_raster(const lut::MaskEngine& engine, const PixelReceivers& pixels, const Camera& camera,
                             const ProgressCallback& progress, BackendStats* stats) const {
  raster::RasterOptions options = options_.raster;
  options.stats = stats != nullptr;
  raster::RasterResult result = raster::occlusion(pixels, *scene_, *triangles_, engine, camera, options, progress);
  if (stats) stats->raster = result.stats;
  return std::move(result.masks);
}

raster::RasterResult Backends::render_raster(const lut::MaskEngine& engine, const Camera& camera, int width, int height,
                                             const ProgressCallback& progress) const {
  return raster::occlusion(*scene_, *triangles_, engine, camera, width, height, options_.raster, progress);
}

}  // namespace exao::cli
