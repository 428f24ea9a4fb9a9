#pragma once
// The backends of DESIGN.md section 5 behind one call, for the subcommands: each is prepared
// once for a scene and a set of rays (Embree scene, triangle set, mask engine, BVH), then asked
// for the masks of any receivers.

#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "bvh/bvh.h"
#include "bvh/traverse.h"
#include "core/embree_reference.h"
#include "core/error.h"
#include "core/isa.h"
#include "core/mask_set.h"
#include "core/progress.h"
#include "core/scene.h"
#include "core/shadow_rays.h"
#include "lut/mask_engine.h"
#include "lut/triangle_set.h"
#include "raster/occlusion.h"

namespace exao::cli {

enum class Method { Embree, Brute, Bvh, Raster };

[[nodiscard]] const char* method_name(Method method);
[[nodiscard]] Result<Method> parse_method(const std::string& name);
/// Every method name, for --help and validation.
[[nodiscard]] std::vector<std::string> method_names();

struct BackendOptions {
  EmbreeOptions embree;
  raster::RasterOptions raster;
  lut::MaskMode masks = lut::MaskMode::Lut;
  int table_resolution = 0;  // 0: the default for N
  bvh::BvhOptions bvh;
  std::optional<Isa> isa;    // the mask kernels' instruction set (nullopt: EXAO_ISA or the best)
};

/// Work counters a backend reports.
struct BackendStats {
  bvh::TraversalStats traversal;
  raster::RasterStats raster;
};

/// Geometry prepared once per scene: the Embree scene (the reference, and primary visibility),
/// the triangle set the masks read, and the BVH when a method needs it.
class Backends {
 public:
  /// The scene must outlive the Backends.
  [[nodiscard]] static Result<Backends> prepare(const Scene& scene, std::span<const Method> methods,
                                                const BackendOptions& options);

  [[nodiscard]] const EmbreeScene& embree() const { return *embree_; }
  [[nodiscard]] const BackendOptions& options() const { return options_; }

  /// The mask engine for `rays` in `mode` (builds the plane table in Lut mode).
  [[nodiscard]] Result<lut::MaskEngine> engine(const ShadowRays& rays, lut::MaskMode mode,
                                               std::optional<Isa> isa = std::nullopt) const;

  /// Masks of the pixel receivers of `camera` by the raster backend (these receivers: the
  /// G-buffer's own, or Embree's when the caller compares methods on the same receivers).
  [[nodiscard]] MaskSet run_raster(const lut::MaskEngine& engine, const PixelReceivers& pixels, const Camera& camera,
                                   const ProgressCallback& progress = {}, BackendStats* stats = nullptr) const;

  /// The raster backend's own G-buffer receivers and their masks.
  [[nodiscard]] raster::RasterResult render_raster(const lut::MaskEngine& engine, const Camera& camera, int width,
                                                   int height, const ProgressCallback& progress = {}) const;

  /// Masks of `receivers` by `method` (not raster: it needs a camera). `engine` is required for
  /// every method but embree.
  [[nodiscard]] MaskSet run(Method method, const ShadowRays& rays, const lut::MaskEngine* engine,
                            std::span<const Receiver> receivers, const ProgressCallback& progress = {},
                            BackendStats* stats = nullptr, std::optional<EmbreeRays> embree_rays = {}) const;

 private:
  const Scene* scene_ = nullptr;
  BackendOptions options_;
  std::unique_ptr<EmbreeScene> embree_;
  std::unique_ptr<lut::TriangleSet> triangles_;
  std::unique_ptr<bvh::Bvh> bvh_;
};

}  // namespace exao::cli
