#include "ssao/comparison.h"

#include <memory>

#include "core/embree_reference.h"
#include "ssao/error_stats.h"

namespace exao::ssao {

std::optional<Method> variant_reference(Method method) {
  if (method == Method::StereoHbaoPlus2d) return Method::StereoHbaoPlus;
  if (list_nodes(method) > 0 || method == Method::AbufferOit) return Method::Abuffer;
  return std::nullopt;
}

Result<SegmentHits> embree_segment_hits(const Scene& scene) {
  Result<EmbreeScene> built = EmbreeScene::build(scene);
  if (!built) return std::unexpected(built.error());
  auto embree = std::make_shared<EmbreeScene>(std::move(*built));
  return segment_hits_by_closest([embree](const glm::dvec3& origin, const glm::dvec3& direction) -> std::optional<double> {
    const auto hit = embree->closest_hit(glm::vec3(origin), glm::vec3(direction));
    if (!hit) return std::nullopt;
    return static_cast<double>(hit->distance);
  });
}

Comparison compare_scene(const Scene& scene, const Camera& camera, int width, int height, CompareOptions options,
                         std::optional<double> stereo, const ExactAo& exact, const SegmentHits& hits) {
  std::vector<Camera> cameras = {camera};
  if (stereo) {
    const auto eyes = stereo_cameras(camera, *stereo);
    cameras = {eyes.first, eyes.second};
    options.stereo_eyes = eyes;
  }
  Comparison out;
  for (const Camera& c : cameras) out.views.push_back(compare_view(scene, c, width, height, options, exact, hits));
  if (stereo) out.pairs = correspond(out.views[0].view, out.views[1].view);
  const ViewResult& main = out.main();
  if (out.pairs) out.exact_stereo = inconsistency(*out.pairs, out.views[0].exact, out.views[1].exact);
  for (std::size_t i = 0; i < main.methods.size(); ++i) {
    const MethodResult& m = main.methods[i];
    MethodComparison row;
    row.error = error_stats(m.ao, main.exact, main.view.valid);
    if (const std::optional<Method> reference = variant_reference(m.method)) {
      for (const MethodResult& full : main.methods) {
        if (full.method != *reference) continue;
        const double ratio = full.seconds > 0.0 ? m.seconds / full.seconds : 0.0;
        row.against = VariantError{*reference, error_stats(m.ao, full.ao, main.view.valid), ratio};
      }
    }
    if (out.pairs) row.stereo = inconsistency(*out.pairs, out.views[0].methods[i].ao, out.views[1].methods[i].ao);
    out.methods.push_back(row);
  }
  return out;
}

}  // namespace exao::ssao
