#pragma once
// exao::engine::Options: every setting of an AO computation, one struct for the exao program
// (render, bake, query, bench) and the public API alike, with its defaults written here once.
//
// Errors about an option name it as the field is named here ("samples", "radius", "bvh.branching")
// followed by a colon, and give the value: "samples: must be a multiple of 32 from 32 to 1024,
// got 100". The exao program turns the name into its flag (cli/option_flags.cpp), the public API
// into "options.<name>"; no library error names a command-line flag.

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include "bvh/bvh.h"
#include "bvh/hybrid.h"
#include "core/cutouts.h"
#include "core/embree_reference.h"
#include "core/enum_names.h"
#include "core/error.h"
#include "core/isa.h"
#include "core/sample_pattern.h"
#include "core/scene.h"
#include "lut/mask_engine.h"
#include "raster/lod.h"
#include "raster/occlusion.h"

namespace exao::engine {

/// The backends of DESIGN.md section 5. Auto (the default) is bvh's traversal with Embree for
/// the rays masks do not decide cheaply or surely (bvh/hybrid.h): Embree's answer on every ray.
enum class Method { Embree, Brute, Bvh, Raster, Auto };

[[nodiscard]] constexpr auto enum_names(Method) {
  return std::to_array<EnumName<Method>>({{Method::Auto, "auto"},
                                          {Method::Embree, "embree"},
                                          {Method::Brute, "brute"},
                                          {Method::Bvh, "bvh"},
                                          {Method::Raster, "raster"}});
}

[[nodiscard]] const char* method_name(Method method);
/// "auto", "embree", "brute", "bvh" or "raster"; the error names the option "method".
[[nodiscard]] Result<Method> parse_method(const std::string& name);

/// Where the default origin offset comes from (Options::offset_default).
enum class OffsetDefault { SceneDiagonal, PointScale };

/// A length in world units, or a percentage of the scene's bounding-box diagonal.
struct Length {
  float value = 0.0f;
  bool percent_of_diagonal = false;

  /// World units for a scene of this bounding-box diagonal.
  [[nodiscard]] float resolve(float diagonal) const { return percent_of_diagonal ? value * 0.01f * diagonal : value; }
};

/// 5% of the diagonal shows contact shadows and creases without darkening whole rooms.
inline constexpr Length kDefaultRadius{5.0f, true};

struct Options {
  /// r: the longest shadow ray, finite and > 0. Default: 5% of the scene's bounding-box diagonal.
  Length radius = kDefaultRadius;
  /// N: rays per receiver, a multiple of 32 from 32 to 1024 (core/sample_pattern.h).
  int samples = 128;
  Falloff falloff = Falloff::Constant;
  std::uint64_t pattern_seed = kDefaultPatternSeed;
  /// The caller's own directions (make_given_pattern) instead of the generated pattern; then
  /// samples must equal its count, and falloff and pattern_seed are not used. nullptr: generated.
  std::shared_ptr<const SamplePattern> given_pattern;
  /// eps: rays start at p + eps n, world units, finite and >= 0. nullopt: offset_default says.
  std::optional<float> origin_offset;
  /// The offset when origin_offset is nullopt: 1e-4 of the scene's diagonal (the exao program,
  /// DESIGN.md section 1), or 1e-4 of each point's largest coordinate magnitude, at least 1e-6
  /// (the public API: core/shadow_rays.h, kPointOffsetFraction).
  OffsetDefault offset_default = OffsetDefault::SceneDiagonal;
  /// Auto: as the scene says (glTF doubleSided; other formats two-sided); One or Two overrides.
  Sidedness sidedness = Sidedness::Auto;
  Method method = Method::Auto;
  /// How auto splits the work between masks and rays: its cost model (the default), or masks to
  /// the end, or rays only (tests and benchmarks; the answer is the same bits in all three).
  bvh::HybridPolicy hybrid = bvh::HybridPolicy::Adaptive;
  /// Where plane masks come from (brute, bvh, raster; auto uses exact masks); embree casts rays
  /// and ignores it.
  lut::MaskMode masks = lut::MaskMode::Exact;  // faster than the table on every level measured (docs/speed.md)
  /// Worker threads, from 0 to max_threads(); 0: one per core. The engine runs everything in a
  /// TBB arena of this size.
  int threads = 0;
  /// Plane table cells per side (masks = lut): 0 for the default for N, else lut::kMinTableResolution
  /// to lut::kMaxTableResolution.
  int table_resolution = 0;
  /// The mask kernels' instruction set (core/isa.h); nullopt: default_isa() (EXAO_ISA, else the
  /// best this CPU runs). A level this CPU does not run is an error when the engine is built.
  std::optional<Isa> isa;
  bvh::BvhOptions bvh;
  raster::RasterOptions raster;
  /// The raster method's level of detail (paper Sec. 4.3, raster/lod.h), which trades exact masks
  /// for speed; nullopt: off (exact). lod->eps1 == 0: auto, raster::auto_lod_eps from the radius
  /// and the pixel size at the receivers' median depth. Only with method raster (check_serves).
  /// Its errors name lod_eps1, lod_levels, lod_k, lod_overlap and lod_filter, as raster/lod.h does.
  std::optional<raster::LodOptions> lod;
  /// How Embree is asked (method embree, and the reference in comparisons).
  EmbreeOptions embree;
  /// Cut-outs (core/cutouts.h): whether glTF MASK materials let rays through where their alpha
  /// is below alphaCutoff (the default), and what BLEND materials do (opaque by default). Every
  /// method but raster serves them; errors name "cutouts", "blend" and "blend_cutoff".
  CutoutPolicy cutouts;
};

/// The most worker threads Options::threads may ask for: oneTBB's ceiling, 256 or 4x the cores.
[[nodiscard]] int max_threads();

/// Checks every field that does not depend on the scene (the radius and offset are checked once
/// resolved, by make_shadow_rays); the error names the first bad field and its value. The one
/// place each rule lives: the sample count in check_sample_count, the table resolution in
/// lut::check_table_resolution, the others here.
[[nodiscard]] Result<void> check_options(const Options& options);

/// The option an error message is about: the leading "name:" when name is an option of this
/// struct ("samples", "bvh.branching", ...), else nullopt. For boundaries that rename options.
[[nodiscard]] std::optional<std::string_view> option_of(std::string_view message);

}  // namespace exao::engine
