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
  }
  return "?";
}

std::vector<std::string> method_names() { return {"embree", "brute", "bvh"}; }

Result<Method> parse_method(const std::string& name) {
  for (const Method m : {Method::Embree, Method::Brute, Method::Bvh}) {
    if (name == method_name(m)) return m;
  }
  return fail("--method: unknown method '" + name + "' (embree, brute or bvh)");
}

Result<Backends> Backends::prepare(const Scene& scene, std::span<const Method> methods, const BackendOptions& options) {
  Backends b;
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

Result<lut::MaskEngine> Backends::engine(const ShadowRays& rays, lut::MaskMode mode) const {
  return lut::MaskEngine::build(rays, mode, options_.table_resolution);
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
  }
  return {};
}

}  // namespace exao::cli
