#pragma once
// What each backend can serve (DESIGN.md section 5), declared once: which receivers, which mask
// modes, sidedness and falloffs. A request a backend cannot serve is refused when the options are
// checked, with one line saying why, in every command and in the API alike.

#include <span>

#include "core/enum_names.h"
#include "core/error.h"
#include "core/sample_pattern.h"
#include "core/scene.h"
#include "engine/options.h"
#include "lut/mask_engine.h"

namespace exao::engine {

/// What a request asks for AO at.
enum class Receivers {
  Points,  // any points with normals (vertices, texels, a renderer's shading points)
  Pixels,  // the pixels of a camera image
};

[[nodiscard]] constexpr auto enum_names(Receivers) {
  return std::to_array<EnumName<Receivers>>({{Receivers::Points, "points"}, {Receivers::Pixels, "pixels"}});
}

[[nodiscard]] const char* receivers_name(Receivers receivers);

struct Capabilities {
  bool points = false;  // any points
  bool pixels = false;  // a camera's pixels (every backend that serves points serves these too)
  /// The mask modes it computes with; empty: it casts rays and options.masks does not apply.
  std::span<const lut::MaskMode> mask_modes;
  std::span<const Sidedness> sidedness;
  std::span<const Falloff> falloffs;
  /// Alpha-tested triangles (core/cutouts.h), exactly as Embree's filter decides them.
  bool cutouts = false;
};

[[nodiscard]] const Capabilities& capabilities(Method method);

/// Whether `options.method` can serve `receivers` with these options; the error names the
/// option ("method", "masks", ...) and what the backend serves instead.
[[nodiscard]] Result<void> check_serves(const Options& options, Receivers receivers);

/// Whether `options.method` can serve a scene that has cut-outs under options.cutouts
/// (`has_cutouts`), before any work on it; the error names "method" and the ways out.
[[nodiscard]] Result<void> check_serves_cutouts(const Options& options, bool has_cutouts);

}  // namespace exao::engine
