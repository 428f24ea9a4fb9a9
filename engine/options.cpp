#include "engine/options.h"

#include <array>
#include <algorithm>
#include <cmath>
#include <thread>

#include "lut/plane_table.h"

namespace exao::engine {
namespace {


// Every field of Options, as errors name them.
constexpr std::array<std::string_view, 29> kOptionNames{
    "radius",       "samples",      "falloff",     "pattern_seed",  "origin_offset", "sidedness",
    "method",       "masks",        "threads",     "table_resolution", "bvh.branching", "bvh.max_leaf_size",
    "raster.alpha", "raster.stats", "embree.rays", "embree.across_receivers", "embree.coherent", "isa",
    "lod",          "lod_eps1",     "lod_levels",  "lod_k",         "lod_overlap",   "lod_filter",
    "raster.ranges", "hybrid",      "cutouts",     "blend",         "blend_cutoff"};

template <class Enum>
bool in_range(Enum value, Enum last) {
  const int v = static_cast<int>(value);
  return v >= 0 && v <= static_cast<int>(last);
}

std::string number(int value) { return std::to_string(value); }

}  // namespace

const char* method_name(Method method) { return name_of(method); }

Result<Method> parse_method(const std::string& name) {
  if (const std::optional<Method> m = parse_enum<Method>(name)) return *m;
  return fail("method: unknown method '" + name + "' (" + name_list<Method>() + "), got '" + name + "'");
}

int max_threads() {
  // oneTBB's own ceiling (above it, it warns and ignores the request): 256, or 4x the cores.
  return std::max(256, 4 * static_cast<int>(std::thread::hardware_concurrency()));
}

Result<void> check_options(const Options& o) {
  if (auto ok = check_sample_count(o.samples); !ok) return ok;
  if (o.given_pattern && o.given_pattern->count != o.samples) {
    return fail("samples: must equal the given pattern's " + number(o.given_pattern->count) + " directions, got " +
                number(o.samples));
  }
  if (!in_range(o.falloff, Falloff::Quadratic)) return fail("falloff: not a falloff, got " + number(static_cast<int>(o.falloff)));
  if (!in_range(o.sidedness, Sidedness::Two)) return fail("sidedness: not a sidedness, got " + number(static_cast<int>(o.sidedness)));
  if (!in_range(o.method, Method::Auto)) return fail("method: not a method, got " + number(static_cast<int>(o.method)));
  if (!in_range(o.hybrid, bvh::HybridPolicy::Rays)) return fail("hybrid: not a policy, got " + number(static_cast<int>(o.hybrid)));
  if (!in_range(o.masks, lut::MaskMode::Exact)) return fail("masks: not a mask mode, got " + number(static_cast<int>(o.masks)));
  if (!in_range(o.embree.rays, EmbreeRays::Packet16)) {
    return fail("embree.rays: not an Embree ray mode, got " + number(static_cast<int>(o.embree.rays)));
  }
  if (o.threads < 0 || o.threads > max_threads()) {
    return fail("threads: must be from 0 (one per core) to " + number(max_threads()) + ", got " + number(o.threads));
  }
  if (o.table_resolution != 0) {
    if (auto ok = lut::check_table_resolution(o.table_resolution); !ok) return ok;
  }
  if (o.isa && !in_range(*o.isa, Isa::Avx512)) return fail("isa: not an instruction set, got " + number(static_cast<int>(*o.isa)));
  if (auto ok = bvh::check_options(o.bvh); !ok) return ok;
  if (!in_range(o.cutouts.blend, BlendRule::Stochastic)) return fail("blend: not a rule, got " + number(static_cast<int>(o.cutouts.blend)));
  if (auto ok = check_policy(o.cutouts); !ok) return ok;
  if (!(std::isfinite(o.raster.alpha) && o.raster.alpha > 0.0f)) {
    return fail("raster.alpha: must be a finite number > 0, got " + std::to_string(o.raster.alpha));
  }
  // The ranges belong to the levels' triangles, which only the engine has (options.lod).
  if (!o.raster.ranges.empty()) return fail("raster.ranges: set by the engine from lod, must be empty");
  if (o.lod) {
    if (!in_range(o.lod->filter, raster::LodFilter::BoundedDistance)) {
      return fail("lod_filter: not a filter, got " + number(static_cast<int>(o.lod->filter)));
    }
    // eps1 0 is auto, resolved against the pixels (Engine::prepare_lod); the rest is checked now.
    raster::LodOptions checked = *o.lod;
    if (checked.eps1 == 0.0f) checked.eps1 = 1.0f;
    if (auto ok = raster::check_lod_options(checked); !ok) return ok;
  }
  return {};
}

std::optional<std::string_view> option_of(std::string_view message) {
  const std::size_t colon = message.find(':');
  if (colon == std::string_view::npos) return std::nullopt;
  const std::string_view head = message.substr(0, colon);
  for (const std::string_view name : kOptionNames) {
    if (head == name) return name;
  }
  return std::nullopt;
}

}  // namespace exao::engine
