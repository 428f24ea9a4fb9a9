#pragma once
// exao::ssao::compare_view: every chosen screen-space method on one camera's G-buffer, and the
// exact AO of the same receivers (through a callback, so this module needs no ray caster), each
// timed. What `exao compare` runs once per view.

#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "core/enum_names.h"
#include "core/error.h"
#include "core/receiver_frame.h"
#include "core/scene.h"
#include "ssao/hbao.h"
#include "ssao/hbao_plus.h"
#include "ssao/list_compression.h"
#include "ssao/sd_hbao_plus.h"
#include "ssao/settings.h"
#include "ssao/stochastic_depth.h"
#include "ssao/svao.h"
#include "ssao/vao.h"
#include "ssao/view.h"

namespace exao::ssao {

enum class Method {
  Hbao, HbaoPlus, Vao, SdHbao, SdSvao, RtSvao, Abuffer,
  StereoHbaoPlus,    // seed 003 Sec. 3: stereo estimate, reprojection, holes, the separable stereo filter
  StereoHbaoPlus2d,  // the same with the full N x N stereo filter
  SdHbaoPlus,        // seed 000 Sec. 3.2: HBAO+ over the stochastic depth map
  MvSdHbaoPlus,      // seed 000 Sec. 3.4, Alg. 3: with a secondary view's stochastic map
  RtSvaoRays,        // seed 001 Sec. 3.8: per-column rays for the flagged samples
  AbufferM4,         // seed 004 Sec. III-B: the lists compressed to m = 4 nodes
  AbufferM8,         // m = 8
  AbufferOit,        // seed 004 Sec. III Eq. 2-4: transparent receivers, blended
};

[[nodiscard]] constexpr auto enum_names(Method) {
  return std::to_array<EnumName<Method>>({{Method::Hbao, "hbao"},
                                          {Method::HbaoPlus, "hbao+"},
                                          {Method::Vao, "vao"},
                                          {Method::SdHbao, "sdao"},
                                          {Method::SdSvao, "svao"},
                                          {Method::RtSvao, "rtsvao"},
                                          {Method::Abuffer, "abuffer"},
                                          {Method::StereoHbaoPlus, "shbao+"},
                                          {Method::StereoHbaoPlus2d, "shbao+2d"},
                                          {Method::SdHbaoPlus, "sdao+"},
                                          {Method::MvSdHbaoPlus, "mvsdao+"},
                                          {Method::RtSvaoRays, "rtsvao-rays"},
                                          {Method::AbufferM4, "abuffer-m4"},
                                          {Method::AbufferM8, "abuffer-m8"},
                                          {Method::AbufferOit, "abuffer-oit"}});
}

/// The name of a method of `exao compare` (not engine::method_name's AO backends): "hbao",
/// "hbao+", "vao", "sdao", "svao", "rtsvao", "abuffer", "shbao+", "shbao+2d", "sdao+", "mvsdao+",
/// "rtsvao-rays", "abuffer-m4", "abuffer-m8", "abuffer-oit".
[[nodiscard]] const char* compare_method_name(Method method);
/// "HBAO", "HBAO+", "VAO", "SD-HBAO", "SD-SVAO", "RT-SVAO", "A-BUFFER", "S-HBAO+", "S-HBAO+ 2D",
/// "SD-HBAO+", "MV-SD-HBAO+", "RT-SVAO RAYS", "A-BUFFER M=4", "A-BUFFER M=8", "A-BUFFER OIT".
[[nodiscard]] const char* method_label(Method method);
[[nodiscard]] std::vector<Method> all_methods();
/// The names of all_methods(), comma-separated.
[[nodiscard]] std::string all_compare_method_names();
/// A comma-separated list of names, each at most once, at least one; "all" is every method.
[[nodiscard]] Result<std::vector<Method>> parse_methods(const std::string& list);
/// Whether the method's passes include the stereo filter instead of the mono blur.
[[nodiscard]] bool is_stereo(Method method);
/// The nodes m of a compressed A-buffer method, 0 for the others.
[[nodiscard]] int list_nodes(Method method);

struct CompareOptions {
  std::vector<Method> methods = all_methods();
  Settings settings;
  HbaoOptions hbao;            // HBAO, SD-HBAO, A-buffer
  HbaoPlusOptions hbao_plus;
  VaoOptions vao;              // VAO, SD-SVAO, RT-SVAO
  StochasticDepthOptions stochastic;
  MultiViewOptions multiview;       // MV-SD-HBAO+'s secondary camera
  bool keep_front_half = true;      // the compressed A-buffers: ListCompression::keep_front_half
  /// Stereo HBAO+'s pair: when set, the compared camera is one of the two (left, right), and
  /// both runs compute the same pair. Otherwise the compared camera is the left eye and the
  /// right one is stereo_ipd to its right (ssao::stereo_cameras' parallel eyes).
  std::optional<std::pair<Camera, Camera>> stereo_eyes;
  double stereo_ipd = 0.065;        // world units, > 0: used when stereo_eyes is not set
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
  std::size_t holes = 0;   // stereo HBAO+: pixels of the other eye evaluated from scratch (Sec. 3.2)
  std::size_t reprojected = 0;  // and those that took a reprojected value
  std::size_t fragments = 0;    // the A-buffer methods: fragments in the (compressed) lists
};

struct ViewResult {
  View view;
  std::vector<float> exact;      // per pixel; 1 where no triangle is seen
  double gbuffer_seconds = 0.0;  // the G-buffer, shared by all
  double exact_seconds = 0.0;
  double fragment_seconds = 0.0; // the A-buffer, when a method needs it
  double other_eye_seconds = 0.0; // stereo HBAO+'s other eye's G-buffer (the renderer's, charged to none)
  std::optional<Camera> secondary;  // MV-SD-HBAO+'s secondary camera, when it ran
  std::vector<MethodResult> methods;
};

/// The G-buffer of `camera` (width x height), its exact AO, and every method of `options` (which
/// must pass check). Times: HBAO, HBAO+ and VAO their walk; SD-HBAO the A-buffer's
/// rasterisation, its stochastic map drawn from it, and its walk; SD-SVAO phase 1, the A-buffer's
/// rasterisation, the stenciled map and phase 2; RT-SVAO phase 1 and the exact AO of the flagged
/// pixels; A-buffer AO the A-buffer's rasterisation and its walk; each its blur. The G-buffer is
/// shared and counted apart (gbuffer_seconds). The new rows: stereo HBAO+ both eyes' L
/// textures, the estimate, the reprojection and the holes, and the stereo filter of both eyes
/// (the other eye's G-buffer apart, other_eye_seconds); SD-HBAO+ and the compressed and OIT
/// A-buffers as the A-buffer does, plus the compression; MV-SD-HBAO+ also the secondary view's
/// A-buffer and map; RT-SVAO with rays phase 1 and the column rays. `hits` must be given when
/// the methods include rtsvao-rays.
[[nodiscard]] ViewResult compare_view(const Scene& scene, const Camera& camera, int width, int height,
                                      const CompareOptions& options, const ExactAo& exact, const SegmentHits& hits = {});

}  // namespace exao::ssao
