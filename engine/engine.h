#pragma once
// exao::engine::Engine: the one AO engine behind `exao render`, `bake`, `query`, `bench` and the
// public API (exao::api::Engine). It takes a scene (or a Geometry prepared from one), one Options
// and a batch of receivers (or a camera, for pixel receivers), and returns AO, blocked-ray counts
// or masks. It owns what every caller used to do for itself:
//  - checking the options and what the method can serve (engine/capabilities.h);
//  - the rays (pattern, radius, offset, resolved against the scene once) and the mask engine;
//  - the order receivers are visited in (engine/morton.h) and batching: a batch is cut into
//    chunks of kChunk receivers, so no call holds more than one chunk's masks;
//  - threads: everything runs in the engine's own TBB arena of options.threads;
//  - the progress callback (over the whole batch) and the work counters;
//  - the AO formula (core/mask_set.h: ao_from_blocked);
//  - the raster levels of detail (options.lod): resolved against the pixels, built once and kept
//    in the geometry for every engine over it (engine/lod_cache.h).

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <utility>
#include <vector>

#include "bvh/traverse.h"
#include "core/camera.h"
#include "core/error.h"
#include "core/mask_set.h"
#include "core/pixel_receivers.h"
#include "core/progress.h"
#include "core/receiver_frame.h"
#include "core/scene.h"
#include "core/shadow_rays.h"
#include "engine/capabilities.h"
#include "engine/geometry.h"
#include "engine/options.h"
#include "lut/mask_engine.h"
#include "raster/stats.h"

namespace exao::engine {

/// Receivers per backend call within a batch: bounds the masks held at once (kChunk * N / 8
/// bytes, 8 MiB at N = 1024) while leaving every call hundreds of tasks for the threads.
inline constexpr std::size_t kChunk = std::size_t{1} << 16;

/// Part `index` of a batch cut into `count` parts for a job spread over processes or machines
/// (exao --shard K/N): whole chunks of kChunk receivers of the engine's Morton order, part K
/// holding chunks [floor(C * K / N), floor(C * (K + 1) / N)) of the batch's C chunks, so parts
/// differ by at most one chunk and each is a coherent piece of the scene. A part may be empty
/// (fewer chunks than parts). Every receiver's answer is the one the whole batch gives it: the
/// chunks are the same chunks, in the same order.
struct Shard {
  std::size_t index = 0;  // in [0, count)
  std::size_t count = 1;  // at least 1
};

/// The chunks [first, second) of a batch of `receivers` receivers that `shard` holds.
[[nodiscard]] std::pair<std::size_t, std::size_t> shard_chunks(std::size_t receivers, Shard shard);
/// The receivers of `shard` (indices into `receivers`), in the order the engine visits them.
[[nodiscard]] std::vector<std::uint32_t> shard_receivers(std::span<const Receiver> receivers, Shard shard);

/// Work counters a backend reports: per receiver for bvh, per culling stage for raster.
struct Stats {
  bvh::TraversalStats traversal;
  raster::RasterStats raster;
};

/// Per-call settings.
struct RunOptions {
  /// (done, total) receivers of the whole call, from worker threads.
  ProgressCallback progress;
  /// When not null, the backend's counters are added to *stats (raster counts are slower).
  Stats* stats = nullptr;
  /// Overrides options.embree.rays for this call (exao bench times several).
  std::optional<EmbreeRays> embree_rays;
  /// Only this part's receivers are computed (shard_receivers); the outputs of the others are
  /// left as they were. Progress counts the part's receivers.
  std::optional<Shard> shard;
  /// When not empty, the blocked-ray counts of every receiver, computed before (the parts of a
  /// sharded job, put together by exao merge): outputs are made from them and nothing is cast.
  /// Masks cannot be made from counts: asking for them fails.
  std::span<const std::uint32_t> supplied_blocked;
};

/// Where a batch's results go: any of these may be empty; a non-empty one holds one entry per
/// receiver (masks: mask_words() words per receiver), in the caller's order.
struct Outputs {
  std::span<float> ao;                // 1 - blocked / N
  std::span<std::uint32_t> blocked;   // blocked rays, in [0, N]
  std::span<std::uint64_t> masks;     // bit i of receiver r: masks[r * mask_words() + i / 64] >> (i % 64)
};

/// The levels of detail an engine with options.lod uses for one set of pixels.
struct LodLevels {
  raster::LodOptions options;                // eps1 resolved (auto: from r and the pixel size)
  bool automatic = false;                    // eps1 was auto
  const raster::LodScene* levels = nullptr;  // owned by the geometry's LodCache
  bool built = false;                        // this call built them
};

/// Pixel receivers of a camera image and their masks, in pixel order.
struct PixelResult {
  PixelReceivers pixels;
  MaskSet masks;
};

class Engine {
 public:
  Engine(Engine&&) noexcept;
  Engine& operator=(Engine&&) noexcept;
  ~Engine();

  /// Checks the options (check_options, then check_serves for `receivers`), prepares the
  /// scene's geometry and builds the rays and the mask engine. The scene need not outlive the
  /// engine. Errors name the option (engine/options.h) or the scene.
  /// `build_progress` gets the BVH build's (done, total) work units, from any thread.
  [[nodiscard]] static Result<Engine> build(const Scene& scene, const Options& options, Receivers receivers,
                                            const ProgressCallback& build_progress = {});
  /// The same from a scene the caller gives away (Geometry::build(Scene&&)): no copy, and its
  /// arrays freed as the backends are built, so that they are not part of the peak memory. The
  /// scene is left empty after a build (untouched when the options are refused).
  [[nodiscard]] static Result<Engine> build(Scene&& scene, const Options& options, Receivers receivers,
                                            const ProgressCallback& build_progress = {});
  /// The same over a Geometry already prepared for options.method (Geometry::serves); the
  /// options' sidedness and bvh settings are the geometry's.
  [[nodiscard]] static Result<Engine> build(std::shared_ptr<const Geometry> geometry, const Options& options,
                                            Receivers receivers);

  [[nodiscard]] const Options& options() const;
  [[nodiscard]] Method method() const { return options().method; }
  [[nodiscard]] const ShadowRays& rays() const;
  [[nodiscard]] int samples() const { return rays().count(); }
  [[nodiscard]] std::size_t mask_words() const { return static_cast<std::size_t>(samples() + 63) / 64; }
  [[nodiscard]] float radius() const { return rays().radius; }
  [[nodiscard]] float origin_offset() const { return rays().origin_offset; }
  /// The mask engine (nullptr for embree, which casts rays).
  [[nodiscard]] const lut::MaskEngine* mask_engine() const;
  [[nodiscard]] const Geometry& geometry() const;
  /// The same geometry, shared: for an engine of other settings over it (build above).
  [[nodiscard]] std::shared_ptr<const Geometry> shared_geometry() const;
  /// Worker threads of the engine's arena.
  [[nodiscard]] int threads() const;

  /// Moves the geometry's triangles (Geometry::refit: 3 vertices per triangle, the scene's
  /// order) for this engine and every other engine over the same geometry. The radius and
  /// offset resolved at build stay as they are. No query of any of those engines may run
  /// meanwhile.
  [[nodiscard]] Result<void> refit(std::span<const glm::vec3> vertices);

  /// AO, counts and/or masks of `receivers` (Receivers::Points). Every receiver must have a
  /// finite position and a normal that can be normalised (the caller checks input). Fails
  /// when an output's size does not match.
  [[nodiscard]] Result<void> run(std::span<const Receiver> receivers, const Outputs& outputs,
                                 const RunOptions& run = {}) const;
  /// run() into a vector of AO values.
  [[nodiscard]] Result<std::vector<float>> ao(std::span<const Receiver> receivers, const RunOptions& run = {}) const;
  /// run() into a MaskSet.
  [[nodiscard]] Result<MaskSet> masks(std::span<const Receiver> receivers, const RunOptions& run = {}) const;

  /// The mask of one receiver into words (mask_words() of them), on the calling thread with no
  /// allocation for bvh and brute: for renderers asking one shading point at a time.
  void mask_one(const Receiver& receiver, std::span<std::uint64_t> words) const;

  /// The pixels of a width x height image of `camera` (1 to 16384 each) and their masks: the
  /// raster backend's own G-buffer receivers, or Embree's primary visibility for the others.
  [[nodiscard]] Result<PixelResult> render(const Camera& camera, int width, int height, const RunOptions& run = {}) const;
  /// The pixel receivers render() computes AO at: the raster backend's own G-buffer, or
  /// Embree's primary visibility for the others.
  [[nodiscard]] Result<PixelReceivers> render_pixels(const Camera& camera, int width, int height) const;
  /// The levels of detail options.lod asks for at these pixels, built on first use and kept in
  /// the geometry (every engine over it reuses them); nullopt when options.lod is off.
  /// pixel_masks calls it too: a caller that times pixel_masks calls it first, so that the
  /// build is not timed. Errors name the option (lod_eps1, lod_levels, ...).
  [[nodiscard]] Result<std::optional<LodLevels>> prepare_lod(const PixelReceivers& pixels, const Camera& camera,
                                                             const ProgressCallback& progress = {}) const;
  /// Masks of pixel receivers the caller already has (of this camera and image size), by any
  /// method: exao bench runs every method on Embree's pixels.
  [[nodiscard]] Result<MaskSet> pixel_masks(const PixelReceivers& pixels, const Camera& camera,
                                            const RunOptions& run = {}) const;
  /// Embree's primary visibility (needs a Geometry built with embree).
  [[nodiscard]] Result<PixelReceivers> pixel_receivers(const Camera& camera, int width, int height) const;

  struct Impl;

 private:
  explicit Engine(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace exao::engine
