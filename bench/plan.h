#pragma once
// exao::bench::Plan: what `exao bench` times. Every method of the plan runs on the same receivers
// with the same rays, once per (N, r), beside Embree, the reference of every comparison. Each
// (N, r) has one row per configuration (configurations()): Embree per ray mode, each other
// method per mask mode and instruction set, and raster with a level of detail per LOD entry.
//
// Errors name the field as it is named here ("repeats", "isa", "embree.rays") or engine::Options
// names it ("samples", "method", "masks"), followed by a colon and the value; never a flag.

#include <optional>
#include <string>
#include <vector>

#include "bake/options.h"
#include "core/embree_reference.h"
#include "core/error.h"
#include "core/isa.h"
#include "engine/engine.h"
#include "lut/mask_engine.h"
#include "raster/lod.h"

namespace exao::bench {

/// One radius of the plan: its length, and its text as the user gave it, which names its rows.
struct Radius {
  engine::Length length;
  std::string text;
};

struct Plan {
  /// The settings every row shares (threads, sidedness, cut-outs, BVH shape, offset, falloff,
  /// ...); each row sets its own method, masks, isa, samples, radius and lod over it.
  engine::Options base;
  /// N, each checked as engine::Options::samples is; at least one.
  std::vector<int> samples{128, 1024};
  /// r; none: no rows.
  std::vector<Radius> radii{{{1.0f, true}, "1%"}, {{5.0f, true}, "5%"}};
  /// The methods timed; embree is added first (the reference) when missing, repeats are dropped.
  std::vector<engine::Method> methods{engine::Method::Embree, engine::Method::Auto, engine::Method::Bvh};
  /// Mask modes of every method but embree (auto: exact only, one row whatever this lists).
  std::vector<lut::MaskMode> masks{lut::MaskMode::Lut, lut::MaskMode::Exact};
  /// Embree's ray modes, one row each; the first is the reference. At least one.
  std::vector<EmbreeRays> embree_rays{EmbreeRays::Packet16};
  /// The mask kernels' instruction sets, one row each (nullopt: default_isa()); each must run on
  /// this CPU. At least one.
  std::vector<std::optional<Isa>> isas{std::nullopt};
  /// raster+lod rows: one per entry, mask mode and instruction set, when methods has raster
  /// (eps1 0: auto). Checked as engine::Options::lod is.
  std::vector<raster::LodOptions> lods;
  /// nullopt: the camera's pixels (Embree's primary visibility). Else a bake's receivers, its
  /// vertices or texels (bake::bake_receivers), checked as bake::check_options checks.
  std::optional<bake::BakeOptions> bake;
  /// Only this part of a bake's receivers (engine::shard_receivers), in the engine's order.
  std::optional<engine::Shard> shard;
  /// Interleaved repeats, at least 1: drift of the machine hits every method alike, and the
  /// fastest time counts.
  int repeats = 1;
  /// Each row keeps the backend's work counters (engine::Stats).
  bool stats = false;
  /// The workload's name in the report ("Conference pixels"); the caller's words.
  std::string label;
};

/// The plan as it runs: methods with embree first and no repeats, every instruction set resolved
/// (resolve_isa), no LOD entries without raster. Checks in this order: repeats, a shard without a
/// bake, the ray modes, the instruction sets, the sample counts, what each method and mask mode
/// serves on the plan's receivers (engine::check_serves), the LOD entries (engine::check_options).
/// The first bad field fails, named with its value: "repeats: must be at least 1, got 0".
[[nodiscard]] Result<Plan> check_plan(Plan plan);

/// One timed configuration of a (N, r): a method with a mask mode and instruction set, or Embree
/// with a ray mode.
struct Config {
  engine::Method method = engine::Method::Embree;
  lut::MaskMode mode = lut::MaskMode::Exact;
  EmbreeRays rays = EmbreeRays::Single;
  std::optional<Isa> isa;
  int lod = -1;  // raster+lod: index into Plan::lods; -1: no level of detail
};

/// The rows of every (N, r) of a checked plan, Embree's first (the reference): Embree per ray
/// mode; each other method per mask mode and instruction set; raster+lod per mask mode,
/// instruction set and LOD entry.
[[nodiscard]] std::vector<Config> configurations(const Plan& plan);

/// The engine options of one row: the plan's base with the row's method, masks, isa, lod, N and r.
[[nodiscard]] engine::Options row_options(const Plan& plan, const Config& config, int samples,
                                          const engine::Length& radius);

}  // namespace exao::bench
