#include "ssao/compare.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>
#include <sstream>

#include "core/world_key.h"
#include "ssao/abuffer_ao.h"
#include "ssao/bilateral.h"
#include "ssao/fragment_buffer.h"
#include "ssao/sd_hbao.h"
#include "ssao/svao.h"

namespace exao::ssao {
namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

bool needs_fragments(Method m) { return m == Method::SdHbao || m == Method::SdSvao || m == Method::Abuffer; }

}  // namespace

const char* method_name(Method method) {
  switch (method) {
    case Method::Hbao: return "hbao";
    case Method::HbaoPlus: return "hbao+";
    case Method::Vao: return "vao";
    case Method::SdHbao: return "sdao";
    case Method::SdSvao: return "svao";
    case Method::RtSvao: return "rtsvao";
    case Method::Abuffer: return "abuffer";
  }
  return "?";
}

const char* method_label(Method method) {
  switch (method) {
    case Method::Hbao: return "HBAO";
    case Method::HbaoPlus: return "HBAO+";
    case Method::Vao: return "VAO";
    case Method::SdHbao: return "SD-HBAO";
    case Method::SdSvao: return "SD-SVAO";
    case Method::RtSvao: return "RT-SVAO";
    case Method::Abuffer: return "A-BUFFER";
  }
  return "?";
}

std::vector<Method> all_methods() {
  return {Method::Hbao, Method::HbaoPlus, Method::Vao, Method::SdHbao, Method::SdSvao, Method::RtSvao, Method::Abuffer};
}

Result<std::vector<Method>> parse_methods(const std::string& list) {
  std::vector<Method> out;
  std::stringstream in(list);
  std::string name;
  while (std::getline(in, name, ',')) {
    bool found = false;
    for (const Method m : all_methods()) {
      if (name != method_name(m)) continue;
      if (std::find(out.begin(), out.end(), m) != out.end()) return fail("methods: '" + name + "' is listed twice");
      out.push_back(m);
      found = true;
    }
    if (!found) return fail("methods: unknown method '" + name + "' (hbao, hbao+, vao, sdao, svao, rtsvao, abuffer)");
  }
  if (out.empty()) return fail("methods: the list is empty (hbao, hbao+, vao, sdao, svao, rtsvao, abuffer)");
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
  if (options.world_key_cell && !(*options.world_key_cell > 0.0f && std::isfinite(*options.world_key_cell))) {
    return fail("key cell: must be a length greater than 0");
  }
  return {};
}

ViewResult compare_view(const Scene& scene, const Camera& camera, int width, int height, const CompareOptions& options,
                        const ExactAo& exact) {
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

  const Settings& s = options.settings;
  for (const Method m : options.methods) {
    MethodResult out{m, {}, 0.0, 0.0, 0};
    start = Clock::now();
    switch (m) {
      case Method::Hbao: out.ao = hbao(view, s, options.hbao); break;
      case Method::HbaoPlus: out.ao = hbao_plus(view, s, options.hbao_plus); break;
      case Method::Vao: out.ao = vao(view, s, options.vao).ao; break;
      case Method::SdHbao: {
        const StochasticDepth map = make_stochastic_depth(*fragments, options.stochastic);
        out.ao = sd_hbao(view, map, s, options.hbao);
        break;
      }
      case Method::SdSvao: {
        const VaoResult phase1 = vao(view, s, options.vao);
        const StochasticDepth map = make_stochastic_depth(*fragments, options.stochastic, phase1.stencil);
        out.ao = sd_svao(view, phase1, map, s, options.vao);
        out.flagged = flagged_pixels(phase1).size();
        break;
      }
      case Method::RtSvao: {
        const VaoResult phase1 = vao(view, s, options.vao);
        const std::vector<std::uint32_t> pixels = flagged_pixels(phase1);
        // The view's receivers are in pixel order: find each flagged pixel's.
        std::vector<Receiver> flagged;
        flagged.reserve(pixels.size());
        std::size_t next = 0;
        for (const std::uint32_t p : pixels) {
          while (view.receivers.pixel[next] != p) ++next;
          flagged.push_back(view.receivers.receivers[next]);
        }
        out.ao = rt_svao(phase1, exact(flagged));
        out.flagged = pixels.size();
        break;
      }
      case Method::Abuffer: out.ao = abuffer_ao(view, *fragments, scene, s, options.hbao); break;
    }
    bilateral_blur(view, s.radius, s.blur_radius, out.ao);
    for (float& v : out.ao) v = std::clamp(v, 0.0f, 1.0f);  // VAO's estimator exceeds 1 before the blur
    // The papers time a stochastic map with its geometry pass (seed 000 Table 2, seed 001
    // Table 1): every method whose maps are drawn from the A-buffer is charged its rasterisation,
    // which all of them share here. The G-buffer is not charged to anyone (seed 000 Sec. 4: the
    // conventional depth map comes with the renderer's G-buffer pass).
    out.map_seconds = needs_fragments(m) ? r.fragment_seconds : 0.0;
    out.seconds = since(start) + out.map_seconds;
    r.methods.push_back(std::move(out));
  }
  return r;
}

}  // namespace exao::ssao
