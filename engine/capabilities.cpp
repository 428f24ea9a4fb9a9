#include "engine/capabilities.h"

#include <algorithm>
#include <array>
#include <string>

namespace exao::engine {
namespace {

constexpr std::array kBothModes{lut::MaskMode::Lut, lut::MaskMode::Exact};
constexpr std::array kExactOnly{lut::MaskMode::Exact};
constexpr std::array kEverySidedness{Sidedness::Auto, Sidedness::One, Sidedness::Two};
constexpr std::array kEveryFalloff{Falloff::Constant, Falloff::Linear, Falloff::Quadratic};

// Every backend casts the same rays (lengths carry the falloff) and calls the one triangle mask
// (which holds the sidedness rule), so only the receivers differ: raster draws a camera's
// G-buffer and has no receiver anywhere else.
const Capabilities kEmbree{true, true, {}, kEverySidedness, kEveryFalloff, true};
const Capabilities kBrute{true, true, kBothModes, kEverySidedness, kEveryFalloff, true};
const Capabilities kBvh{true, true, kBothModes, kEverySidedness, kEveryFalloff, true};
// Auto's certainty margins are those of the exact test; a table's cells carry larger errors.
const Capabilities kAuto{true, true, kExactOnly, kEverySidedness, kEveryFalloff, true};
// Raster's influence volumes, LOD levels and fragment tests know nothing of alpha: refused.
const Capabilities kRaster{false, true, kBothModes, kEverySidedness, kEveryFalloff, false};

template <class T>
bool holds(std::span<const T> values, T value) {
  return std::find(values.begin(), values.end(), value) != values.end();
}

}  // namespace

const char* receivers_name(Receivers receivers) { return name_of(receivers); }

const Capabilities& capabilities(Method method) {
  switch (method) {
    case Method::Embree: return kEmbree;
    case Method::Brute: return kBrute;
    case Method::Bvh: return kBvh;
    case Method::Raster: return kRaster;
    case Method::Auto: return kAuto;
  }
  return kBvh;
}

Result<void> check_serves(const Options& options, Receivers receivers) {
  const Capabilities& c = capabilities(options.method);
  const std::string method = method_name(options.method);
  if (receivers == Receivers::Points && !c.points) {
    return fail("method: " + method + " computes AO only at the pixels of a camera image, not at arbitrary points" +
                " (vertices, texels, query points); use bvh, brute or embree, got " + method);
  }
  if (receivers == Receivers::Pixels && !c.pixels) {
    return fail("method: " + method + " cannot compute AO at a camera's pixels, got " + method);
  }
  if (!c.mask_modes.empty() && !holds(c.mask_modes, options.masks)) {
    return fail(std::string("masks: ") + method + " has no " + lut::mask_mode_name(options.masks) + " masks, got " +
                lut::mask_mode_name(options.masks));
  }
  if (options.lod && options.method != Method::Raster) {
    return fail("lod: only the raster method has levels of detail, got method " + method);
  }
  if (!holds(c.sidedness, options.sidedness)) return fail("sidedness: not served by " + method);
  if (!holds(c.falloffs, options.falloff)) {
    return fail(std::string("falloff: ") + method + " has no " + falloff_name(options.falloff) + " falloff, got " +
                falloff_name(options.falloff));
  }
  return {};
}

Result<void> check_serves_cutouts(const Options& options, bool has_cutouts) {
  if (!has_cutouts || capabilities(options.method).cutouts) return {};
  return fail(std::string("method: ") + method_name(options.method) +
              " does not handle cut-outs (alphaMode MASK); use auto, bvh, brute or embree, or cutouts off, got " +
              method_name(options.method));
}

}  // namespace exao::engine
