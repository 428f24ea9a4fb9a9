#pragma once
// exao::ssao::compare_view: every chosen screen-space method on one camera's G-buffer, and the
// exact AO of the same receivers (through a callback, so this module needs no ray caster), each
// timed. What `exao compare` runs once per view.

#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/receiver_frame.h"
#include "core/scene.h"
#include "ssao/hbao.h"
#include "ssao/hbao_plus.h"
#include "ssao/settings.h"
#include "ssao/stochastic_depth.h"
#include "ssao/vao.h"
#include "ssao/view.h"

namespace exao::ssao {

enum class Method { Hbao, HbaoPlus, Vao, SdHbao, SdSvao, RtSvao, Abuffer };

/// "hbao", "hbao+", "vao", "sdao", "svao", "rtsvao", "abuffer".
[[nodiscard]] const char* method_name(Method method);
/// "HBAO", "HBAO+", "VAO", "SD-HBAO", "SD-SVAO", "RT-SVAO", "A-BUFFER".
[[nodiscard]] const char* method_label(Method method);
[[nodiscard]] std::vector<Method> all_methods();
/// A comma-separated list of names, each at most once, at least one.
[[nodiscard]] Result<std::vector<Method>> parse_methods(const std::string& list);

struct CompareOptions {
  std::vector<Method> methods = all_methods();
  Settings settings;
  HbaoOptions hbao;            // HBAO, SD-HBAO, A-buffer
  HbaoPlusOptions hbao_plus;
  VaoOptions vao;              // VAO, SD-SVAO, RT-SVAO
  StochasticDepthOptions stochastic;
  /// Exact AO's receiver keys: the pixel index (exao render's), or world_key of the position
  /// with this cell size (world units, > 0).
  std::optional<float> world_key_cell;
};

[[nodiscard]] Result<void> check(const CompareOptions& options);

/// Exact AO (1 open, 0 occluded) of each receiver, in order.
using ExactAo = std::function<std::vector<float>(std::span<const Receiver> receivers)>;

struct MethodResult {
  Method method;
  std::vector<float> ao;   // per pixel, after the blur; 1 where no triangle is seen
  double seconds = 0.0;    // the method's own passes, its maps' geometry pass included (see compare_view)
  double map_seconds = 0.0; // of which the A-buffer rasterisation its maps are drawn from
  std::size_t flagged = 0; // SD-SVAO and RT-SVAO: pixels phase 1 flagged
};

struct ViewResult {
  View view;
  std::vector<float> exact;      // per pixel; 1 where no triangle is seen
  double gbuffer_seconds = 0.0;  // the G-buffer, shared by all
  double exact_seconds = 0.0;
  double fragment_seconds = 0.0; // the A-buffer, when a method needs it
  std::vector<MethodResult> methods;
};

/// The G-buffer of `camera` (width x height), its exact AO, and every method of `options` (which
/// must pass check). Times: HBAO, HBAO+ and VAO their walk; SD-HBAO the A-buffer's
/// rasterisation, its stochastic map drawn from it, and its walk; SD-SVAO phase 1, the A-buffer's
/// rasterisation, the stenciled map and phase 2; RT-SVAO phase 1 and the exact AO of the flagged
/// pixels; A-buffer AO the A-buffer's rasterisation and its walk; each its blur. The G-buffer is
/// shared and counted apart (gbuffer_seconds).
[[nodiscard]] ViewResult compare_view(const Scene& scene, const Camera& camera, int width, int height,
                                      const CompareOptions& options, const ExactAo& exact);

}  // namespace exao::ssao
