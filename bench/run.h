#pragma once
// exao::bench::prepare and run: the timing loop of `exao bench`. One geometry serves every row;
// the receivers are chosen once (Embree's pixels of the camera, or a bake's), so that every method
// casts the same rays; then per (N, r) every row of the plan is timed, repeats interleaved, and
// compared with the reference row (bench/ratios.h). The library never prints: what a caller shows
// while the rows run comes through Events.

#include <cstddef>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "bake/document.h"
#include "bench/plan.h"
#include "bench/report.h"
#include "core/camera.h"
#include "core/error.h"
#include "core/mask_set.h"
#include "core/pixel_receivers.h"
#include "core/progress.h"
#include "core/scene.h"
#include "engine/engine.h"

namespace exao::bench {

/// What a plan runs on.
struct Workload {
  std::string name;   // the scene as the user named it: the report's scene, and errors' subject
  Scene scene;        // the triangles every method computes AO against
  /// With Plan::bake: the document whose bake's receivers are timed (open_document).
  std::optional<bake::Document> document;
  /// The camera: its pixels are the receivers without Plan::bake, and its pixel size sets an
  /// automatic LOD's eps_1 either way. width and height from 1 to 16384.
  Camera camera;
  int width = 0;
  int height = 0;
};

/// The document a plan with `bake` reads its receivers from, as `exao bake` reads it: a glTF file
/// as it is, another format converted, a mesh without UVs given a box-projection atlas laid out
/// for the texture's size. Errors name the file.
[[nodiscard]] Result<bake::Document> open_document(const std::string& name_or_path, const bake::BakeOptions& bake);

/// The geometry, the reference engine and the receivers every row shares.
struct Setup {
  std::shared_ptr<const engine::Geometry> geometry;
  /// Embree, exact, the plan's first N and r (or the base radius without radii): its threads are
  /// the report's, and its primary visibility gives pixel receivers.
  std::optional<engine::Engine> reference;
  /// The receivers every row is timed on: pixels of the camera, or a bake's in one row of
  /// `width` (with Plan::shard, its part only).
  PixelReceivers receivers;
  std::size_t all_receivers = 0;  // the bake's receivers before Plan::shard took its part
  /// The report's workload (label, scene, triangles, receivers, threads, size), no runs yet.
  Report report;
};

/// Builds the geometry and the reference engine of a checked plan (check_plan) and chooses the
/// receivers. Fails as the engine and bake::bake_receivers do, or when a bake has no receivers
/// ("<name>: the bake has no receivers"); empty pixels or an empty shard are check_receivers's.
[[nodiscard]] Result<Setup> prepare(const Plan& plan, Workload& workload);

/// Fails when there is nothing to time: "<name>: the camera sees no triangle", or "shard: part K
/// of N has no receivers (...)".
[[nodiscard]] Result<void> check_receivers(const Plan& plan, const Workload& workload, const Setup& setup);

/// What a caller is told while the rows run; every member may be empty.
struct Events {
  /// The first row's engine of each radius, on the plan's first N: for notes on its radius and
  /// ray offset.
  std::function<void(const engine::Engine&)> radius_ready;
  /// A raster+lod row's levels, when they were built (before the clock starts; not timed).
  std::function<void(const engine::LodLevels&)> lod_built;
  /// A long step begins (label "lod", or "bench " and the row's method): the callback it reports
  /// its (done, total) receivers or units to, from worker threads. progress_finished follows.
  std::function<ProgressCallback(const std::string& label)> progress_started;
  std::function<void()> progress_finished;
  /// A finished row, with its masks (of setup.receivers, in order), after its ratios; an error
  /// stops the run and is run()'s.
  std::function<Result<void>(const Run& run, const MaskSet& masks)> row;
};

/// Times every row of the plan per (N, r), N outer, radii inner, and returns the report with
/// every run. Fails as the engine does, as check_receivers does, or with the first error
/// events.row returns.
[[nodiscard]] Result<Report> run(const Plan& plan, const Workload& workload, const Setup& setup,
                                 const Events& events = {});

}  // namespace exao::bench
