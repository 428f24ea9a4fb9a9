#pragma once
// exao::ssao::compare_scene: the loop of `exao compare`. Every screen-space method of the options
// on one camera's G-buffer (or both eyes' with stereo), each measured against the exact AO of
// the same pixels: its error, a variant's error against the row it approximates, and with
// stereo, each row's inconsistency between the eyes (seed 003). The caller writes and prints.

#include <optional>
#include <vector>

#include "core/ao_error.h"
#include "core/camera.h"
#include "core/error.h"
#include "core/scene.h"
#include "ssao/compare.h"
#include "ssao/stereo.h"
#include "ssao/svao.h"

namespace exao::ssao {

/// A variant against the row it approximates, when both ran: the compressed lists and the
/// transparent receivers against the A-buffer (seed 004 Sec. V-A), the 2D stereo filter against
/// the separable one (seed 003 Fig. 7).
struct VariantError {
  Method reference;
  AoError error;            // the variant's AO against the reference row's, on valid pixels
  double time_ratio = 0.0;  // variant seconds / reference seconds (0 when the reference took none)
};

/// One method's row: ViewResult::methods of the main view, in order.
struct MethodComparison {
  AoError error;                         // against the exact AO, on the main view's valid pixels
  std::optional<VariantError> against;
  std::optional<Inconsistency> stereo;   // with stereo: between the eyes
};

struct Comparison {
  std::vector<ViewResult> views;         // the main view; with stereo, the left then the right eye
  std::optional<Correspondence> pairs;   // with stereo: the left pixels the right eye sees
  std::optional<Inconsistency> exact_stereo;
  std::vector<MethodComparison> methods;
  /// The main view's result: views.front().
  [[nodiscard]] const ViewResult& main() const { return views.front(); }
};

/// The method a variant is measured against (see VariantError), or nullopt for a method that is
/// no variant.
[[nodiscard]] std::optional<Method> variant_reference(Method method);

/// RT-SVAO's column rays (rtsvao-rays) through Embree's nearest hits, either face; the Embree
/// scene lives as long as the callback. Fails as EmbreeScene::build does.
[[nodiscard]] Result<SegmentHits> embree_segment_hits(const Scene& scene);

/// Every method of `options` (which must pass check) on `camera` (width x height), against
/// `exact`. With `stereo` (the eye distance, world units, > 0): both eyes of
/// stereo_cameras(camera, *stereo), each compared, and options.stereo_eyes set to them. `hits`
/// as compare_view needs it.
[[nodiscard]] Comparison compare_scene(const Scene& scene, const Camera& camera, int width, int height,
                                       CompareOptions options, std::optional<double> stereo, const ExactAo& exact,
                                       const SegmentHits& hits = {});

}  // namespace exao::ssao
