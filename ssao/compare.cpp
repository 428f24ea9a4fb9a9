#include "ssao/compare.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>
#include <sstream>

#include "core/world_key.h"
#include <cassert>
#include <utility>

#include "ssao/abuffer_ao.h"
#include "ssao/abuffer_oit.h"
#include "ssao/bilateral.h"
#include "ssao/fragment_buffer.h"
#include "ssao/sd_hbao.h"
#include "ssao/stereo.h"
#include "ssao/stereo_filter.h"
#include "ssao/stereo_hbao_plus.h"
#include "ssao/svao.h"

namespace exao::ssao {
namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

bool needs_fragments(Method m) {
  switch (m) {
    case Method::SdHbao: case Method::SdSvao: case Method::Abuffer: case Method::SdHbaoPlus: case Method::MvSdHbaoPlus:
    case Method::AbufferM4: case Method::AbufferM8: case Method::AbufferOit:
      return true;
    default:
      return false;
  }
}

}  // namespace

const char* compare_method_name(Method method) { return name_of(method); }

const char* method_label(Method method) {
  switch (method) {
    case Method::Hbao: return "HBAO";
    case Method::HbaoPlus: return "HBAO+";
    case Method::Vao: return "VAO";
    case Method::SdHbao: return "SD-HBAO";
    case Method::SdSvao: return "SD-SVAO";
    case Method::RtSvao: return "RT-SVAO";
    case Method::Abuffer: return "A-BUFFER";
    case Method::StereoHbaoPlus: return "S-HBAO+";
    case Method::StereoHbaoPlus2d: return "S-HBAO+ 2D";
    case Method::SdHbaoPlus: return "SD-HBAO+";
    case Method::MvSdHbaoPlus: return "MV-SD-HBAO+";
    case Method::RtSvaoRays: return "RT-SVAO RAYS";
    case Method::AbufferM4: return "A-BUFFER M=4";
    case Method::AbufferM8: return "A-BUFFER M=8";
    case Method::AbufferOit: return "A-BUFFER OIT";
  }
  return "?";
}

std::vector<Method> all_methods() {
  constexpr auto methods = all_values<Method>();
  return {methods.begin(), methods.end()};
}

std::string all_compare_method_names() { return name_list<Method>(", "); }

bool is_stereo(Method method) { return method == Method::StereoHbaoPlus || method == Method::StereoHbaoPlus2d; }

int list_nodes(Method method) { return method == Method::AbufferM4 ? 4 : method == Method::AbufferM8 ? 8 : 0; }

Result<std::vector<Method>> parse_methods(const std::string& list) {
  std::vector<Method> out;
  std::stringstream in(list);
  std::string name;
  while (std::getline(in, name, ',')) {
    if (name == "all") {
      for (const Method m : all_methods()) {
        if (std::find(out.begin(), out.end(), m) != out.end()) return fail("methods: '" + std::string(compare_method_name(m)) + "' is listed twice");
        out.push_back(m);
      }
      continue;
    }
    bool found = false;
    for (const Method m : all_methods()) {
      if (name != compare_method_name(m)) continue;
      if (std::find(out.begin(), out.end(), m) != out.end()) return fail("methods: '" + name + "' is listed twice");
      out.push_back(m);
      found = true;
    }
    if (!found) return fail("methods: unknown method '" + name + "' (all, " + all_compare_method_names() + ")");
  }
  if (out.empty()) return fail("methods: the list is empty (all, " + all_compare_method_names() + ")");
  return out;
}

Result<void> check(const CompareOptions& options) {
  if (options.methods.empty()) return fail("methods: the list is empty");
  if (!(options.settings.radius > 0.0)) return fail("radius: must be greater than 0");
  if (options.settings.blur_radius < 0 || options.settings.blur_radius > 32) {
    return fail("blur: must be from 0 to 32 pixels, got " + std::to_string(options.settings.blur_radius));
  }
  if (auto ok = check(options.hbao); !ok) return ok;
  if (auto ok = check(options.hbao_plus); !ok) return ok;
  if (auto ok = check(options.vao); !ok) return ok;
  if (auto ok = check(options.stochastic); !ok) return ok;
  if (auto ok = check(options.multiview); !ok) return ok;
  if (!(options.stereo_ipd > 0.0 && std::isfinite(options.stereo_ipd))) return fail("stereo eye distance: must be greater than 0");
  if (options.world_key_cell && !(*options.world_key_cell > 0.0f && std::isfinite(*options.world_key_cell))) {
    return fail("key cell: must be a length greater than 0");
  }
  return {};
}

namespace {

// What every method of one view draws from: the view, its scene and options, the A-buffer when
// a method needs it, the other eye for the stereo rows, and the exact AO and column rays.
struct MethodInputs {
  const Scene& scene;
  const View& view;
  const CompareOptions& options;
  const FragmentBuffer* fragments;  // when a method needs it
  const View* other_eye;            // the stereo rows: the other eye's G-buffer
  bool this_is_left = true;
  const ExactAo& exact;
  const SegmentHits& hits;
  int width = 0;
  int height = 0;
};

// Stereo HBAO+'s raw pair: computed once, for both stereo rows, and charged to each.
struct StereoCache {
  std::optional<StereoObscurance> raw;
  double seconds = 0.0;
};

// Stereo HBAO+'s other eye: the given pair's other camera, or stereo_ipd to the right; nullopt
// when no stereo row runs. `this_is_left` says which of the pair `camera` is.
std::optional<Camera> other_eye_camera(const Camera& camera, const CompareOptions& options, bool& this_is_left) {
  this_is_left = true;
  if (std::none_of(options.methods.begin(), options.methods.end(), is_stereo)) return std::nullopt;
  if (options.stereo_eyes) {
    this_is_left = camera.eye == options.stereo_eyes->first.eye;
    return this_is_left ? options.stereo_eyes->second : options.stereo_eyes->first;
  }
  Camera other = camera;
  other.eye = camera.eye + static_cast<float>(options.stereo_ipd) * glm::normalize(glm::cross(camera.forward, camera.up));
  other.name = camera.name + "-right";
  return other;
}

// RT-SVAO: VAO's phase 1, then the exact AO of the flagged pixels.
void rt_svao_row(const MethodInputs& in, MethodResult& out) {
  const View& view = in.view;
  const VaoResult phase1 = vao(view, in.options.settings, in.options.vao);
  const std::vector<std::uint32_t> pixels = flagged_pixels(phase1);
  // The view's receivers are in pixel order: find each flagged pixel's.
  std::vector<Receiver> flagged;
  flagged.reserve(pixels.size());
  std::size_t next = 0;
  for (const std::uint32_t p : pixels) {
    while (view.receivers.pixel[next] != p) ++next;
    flagged.push_back(view.receivers.receivers[next]);
  }
  out.ao = rt_svao(phase1, in.exact(flagged));
  out.flagged = pixels.size();
}

// Stereo HBAO+ (separable or full filter): this eye's AO of the pair; returns the seconds of
// both eyes' passes, the raw pair's and this row's filter.
double stereo_row(const MethodInputs& in, Method m, StereoCache& cache, MethodResult& out) {
  const Settings& s = in.options.settings;
  const View& left = in.this_is_left ? in.view : *in.other_eye;
  const View& right = in.this_is_left ? *in.other_eye : in.view;
  if (!cache.raw) {
    const auto raw_start = Clock::now();
    cache.raw = stereo_hbao_plus(left, right, s, in.options.hbao_plus);
    cache.seconds = since(raw_start);
  }
  std::vector<float> left_ao = cache.raw->left, right_ao = cache.raw->right;
  const auto filter_start = Clock::now();
  StereoFilterOptions filter;
  filter.radius = s.blur_radius;
  filter.form = m == Method::StereoHbaoPlus ? StereoFilterForm::Separable : StereoFilterForm::Full;
  stereo_filter(left, right, left_ao, right_ao, filter);
  const double seconds = cache.seconds + since(filter_start);
  out.ao = in.this_is_left ? std::move(left_ao) : std::move(right_ao);
  out.holes = cache.raw->holes;
  out.reprojected = cache.raw->reprojected;
  return seconds;
}

// MV-SD-HBAO+: the view's stochastic map with a secondary view's; returns the seconds of the
// secondary view's A-buffer (a geometry pass of this method's own).
double multiview_row(const MethodInputs& in, std::optional<Camera>& secondary, MethodResult& out) {
  const CompareOptions& options = in.options;
  const StochasticDepth map = make_stochastic_depth(*in.fragments, options.stochastic);
  const Camera second = secondary_camera(in.view, options.multiview);
  secondary = second;
  const auto map_start = Clock::now();
  const FragmentBuffer second_fragments = rasterize_fragments(in.scene, second, in.width, in.height);
  const double seconds = since(map_start);
  const StochasticDepth second_map = make_stochastic_depth(second_fragments, options.stochastic);
  out.ao = multiview_sd_hbao_plus(in.view, map, {DepthCamera{view_basis(second, in.width, in.height), &second_map}},
                                  options.settings, options.hbao_plus);
  return seconds;
}

// One method's AO (before the blur) and counts into `out`; returns the seconds of the geometry
// passes or both eyes' passes it is charged apart (0 for most).
double method_ao(Method m, const MethodInputs& in, StereoCache& stereo, std::optional<Camera>& secondary, MethodResult& out) {
  const View& view = in.view;
  const CompareOptions& options = in.options;
  const Settings& s = options.settings;
  switch (m) {
    case Method::Hbao: out.ao = hbao(view, s, options.hbao); break;
    case Method::HbaoPlus: out.ao = hbao_plus(view, s, options.hbao_plus); break;
    case Method::Vao: out.ao = vao(view, s, options.vao).ao; break;
    case Method::SdHbao: {
      const StochasticDepth map = make_stochastic_depth(*in.fragments, options.stochastic);
      out.ao = sd_hbao(view, map, s, options.hbao);
      break;
    }
    case Method::SdSvao: {
      const VaoResult phase1 = vao(view, s, options.vao);
      const StochasticDepth map = make_stochastic_depth(*in.fragments, options.stochastic, phase1.stencil);
      out.ao = sd_svao(view, phase1, map, s, options.vao);
      out.flagged = flagged_pixels(phase1).size();
      break;
    }
    case Method::RtSvao: rt_svao_row(in, out); break;
    case Method::Abuffer:
      out.ao = abuffer_ao(view, *in.fragments, in.scene, s, options.hbao);
      out.fragments = in.fragments->fragments.size();
      break;
    case Method::StereoHbaoPlus:
    case Method::StereoHbaoPlus2d: return stereo_row(in, m, stereo, out);
    case Method::SdHbaoPlus: {
      const StochasticDepth map = make_stochastic_depth(*in.fragments, options.stochastic);
      out.ao = sd_hbao_plus(view, map, s, options.hbao_plus);
      break;
    }
    case Method::MvSdHbaoPlus: return multiview_row(in, secondary, out);
    case Method::RtSvaoRays: {
      assert(in.hits && "compare_view: rtsvao-rays needs the segment hits");
      const VaoResult phase1 = vao(view, s, options.vao);
      out.ao = rt_svao_columns(view, phase1, s, options.vao, in.hits);
      out.flagged = flagged_pixels(phase1).size();
      break;
    }
    case Method::AbufferM4:
    case Method::AbufferM8: {
      ListCompression compression;
      compression.nodes = list_nodes(m);
      compression.keep_front_half = options.keep_front_half;
      const FragmentBuffer compressed = compress_fragments(*in.fragments, view, in.scene, compression);
      out.ao = abuffer_ao(view, compressed, in.scene, s, options.hbao);
      out.fragments = compressed.fragments.size();
      break;
    }
    case Method::AbufferOit:
      out.ao = abuffer_oit_ao(view, *in.fragments, in.scene, s, options.hbao);
      out.fragments = in.fragments->fragments.size();
      break;
  }
  return 0.0;
}

}  // namespace

ViewResult compare_view(const Scene& scene, const Camera& camera, int width, int height, const CompareOptions& options,
                        const ExactAo& exact, const SegmentHits& hits) {
  ViewResult r;
  auto start = Clock::now();
  r.view = make_view(scene, camera, width, height);
  r.gbuffer_seconds = since(start);
  View& view = r.view;
  if (options.world_key_cell) {
    for (Receiver& receiver : view.receivers.receivers) receiver.key = world_key(receiver.position, *options.world_key_cell);
  }

  start = Clock::now();
  {
    const std::vector<float> values = exact(view.receivers.receivers);
    r.exact.assign(view.pixel_count(), 1.0f);
    for (std::size_t i = 0; i < values.size(); ++i) r.exact[view.receivers.pixel[i]] = values[i];
  }
  r.exact_seconds = since(start);

  std::optional<FragmentBuffer> fragments;
  if (std::any_of(options.methods.begin(), options.methods.end(), needs_fragments)) {
    start = Clock::now();
    fragments = rasterize_fragments(scene, camera, width, height);
    r.fragment_seconds = since(start);
  }

  // Stereo HBAO+'s pair: this view and the other eye's G-buffer, left first.
  std::optional<View> other_eye;
  bool this_is_left = true;
  if (const std::optional<Camera> other = other_eye_camera(camera, options, this_is_left)) {
    start = Clock::now();
    other_eye = make_view(scene, *other, width, height);
    r.other_eye_seconds = since(start);
  }
  const MethodInputs inputs{scene, view, options, fragments ? &*fragments : nullptr, other_eye ? &*other_eye : nullptr,
                            this_is_left, exact, hits, width, height};
  StereoCache stereo;

  const Settings& s = options.settings;
  for (const Method m : options.methods) {
    MethodResult out{m, {}, 0.0, 0.0, 0, 0, 0, 0};
    start = Clock::now();
    // Geometry passes of this method's own (the secondary view's A-buffer), or both eyes' passes.
    const double extra_map_seconds = method_ao(m, inputs, stereo, r.secondary, out);
    if (!is_stereo(m)) bilateral_blur(view, s.radius, s.blur_radius, out.ao);  // the stereo rows have their own filter
    for (float& v : out.ao) v = std::clamp(v, 0.0f, 1.0f);  // VAO's estimator exceeds 1 before the blur
    // The papers time a stochastic map with its geometry pass (seed 000 Table 2, seed 001
    // Table 1): every method whose maps are drawn from the A-buffer is charged its rasterisation,
    // which all of them share here. The G-buffer is not charged to anyone (seed 000 Sec. 4: the
    // conventional depth map comes with the renderer's G-buffer pass).
    out.map_seconds = needs_fragments(m) ? r.fragment_seconds : 0.0;
    if (m == Method::MvSdHbaoPlus) out.map_seconds += extra_map_seconds;
    out.seconds = is_stereo(m) ? extra_map_seconds : since(start) + (needs_fragments(m) ? r.fragment_seconds : 0.0);
    r.methods.push_back(std::move(out));
  }
  return r;
}

}  // namespace exao::ssao
