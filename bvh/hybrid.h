#pragma once
// exao::bvh::hybrid_occlusion: the `auto` method (DESIGN.md section 5). Masks first, by the
// certain BVH traversal (bvh/traverse-inl.h) under a cost model; then Embree casts the rays the
// masks left undecided: every open ray of a receiver where masking stopped paying, and every ray
// that grazes a triangle the masks tested. Every other ray the masks decided with a margin that
// Embree's rounding cannot cross (lut/kernels-inl.h, "Certain masks"), so the answer is
// Embree's on every ray, whatever the split: the cost model changes the time, never a bit.
//
// The cost model (why it is this one): a mask saves one Embree ray for each ray it decides, and
// costs its work. Both prices differ by machine, scene, radius and N, so they are measured as
// the job runs: each task of 64 neighbouring receivers times its mask phase (per unit of work:
// one node's children or one leaf triangle) and its Embree phase (per ray cast), which gives the
// price of a unit in rays (MaskBudget::rays_per_unit). Each receiver masks while the work spent
// is at most the rays decided so far plus an allowance (bvh/traverse.h), then Embree casts every
// open ray: the near, large occluders that block many rays for little work are masked, and the
// long tail of small ones is left to rays unless the allowance is large enough to reach the end
// (where masks decide the open rays too, and Embree casts only the grazing ones).
// The allowance is one of five levels, 0, N/16, N/4, N and unbounded (masks to the end), and
// which one pays is measured, not predicted: a thread keeps the running average of the wall time
// per receiver of each level on its recent tasks (each level tried once on a thread's first five
// tasks), follows the cheapest, and now and then gives a task to a neighbouring level
// (alternately above and below; every 16th task, the interval doubling up to 256 while the
// neighbour proves no better), so that a change of geometry along the Morton order is noticed
// (neighbouring receivers see the same geometry: what the last tasks cost is the best guess for
// the next). The prices are ratios of sums over recent tasks
// (each decayed by 0.9 a task), so a task that casts a handful of rays weighs little.

#include <atomic>
#include <cstdint>
#include <span>
#include <string>

#include "bvh/bvh.h"
#include "bvh/traverse.h"
#include "core/embree_reference.h"
#include "core/enum_names.h"
#include "core/error.h"
#include "core/mask_set.h"
#include "core/progress.h"
#include "core/receiver_frame.h"
#include "lut/mask_engine.h"

namespace exao::bvh {

/// How the auto method splits work: the cost model, or a fixed split for tests and benchmarks.
enum class HybridPolicy {
  Adaptive,  // the cost model above (the default)
  Masks,     // masks to the end; Embree only on the rays that graze
  Rays,      // no mask work at all: Embree on every ray
};

[[nodiscard]] constexpr auto enum_names(HybridPolicy) {
  return std::to_array<EnumName<HybridPolicy>>(
      {{HybridPolicy::Adaptive, "adaptive"}, {HybridPolicy::Masks, "masks"}, {HybridPolicy::Rays, "rays"}});
}

[[nodiscard]] const char* hybrid_policy_name(HybridPolicy policy);
/// "adaptive", "masks" or "rays"; the error names the option "hybrid".
[[nodiscard]] Result<HybridPolicy> parse_hybrid_policy(const std::string& name);

/// The learning state of one thread (the cost model above).
struct HybridController {
  static constexpr int kLevels = 5;
  static constexpr int kUnbounded = kLevels - 1;
  /// Every kExplorePeriod-th task tries a level next to the best: often enough to follow the
  /// geometry along the Morton order (a few hundred receivers), rare enough that trying a worse
  /// level costs a few percent.
  static constexpr std::uint64_t kExplorePeriod = 16;
  /// ... and each time the neighbour's task costs more than the best level's average, the period
  /// doubles, up to this many tasks: on uniform work (a bake of one dense asset, where rays
  /// alone win) trying a worse level every sixteenth task cost 5-10%. A neighbour's task that
  /// costs less resets it.
  static constexpr std::uint64_t kMaxExplorePeriod = 256;
  float rays_per_unit = 0.5f;   // price of one unit of mask work in Embree rays (measured)
  double cost[kLevels] = {};    // ns per receiver of each allowance level, running average (0: not tried)
  int level = 0;                // the level of the next task
  std::uint64_t tasks = 0;
  std::uint64_t explore_period = kExplorePeriod;
  std::uint64_t next_explore = kExplorePeriod;  // the task count at which to try a neighbour
  int explored_from = -1;       // the best level when this task tried a neighbour (-1: it did not)
  std::uint64_t explorations = 0;
  // Decayed sums of the prices' measurements: mask time and units, Embree time and rays.
  double mask_ns = 0.0, mask_units = 0.0, ray_ns = 0.0, rays = 0.0;

  /// The allowance, in rays, of `level` for N rays.
  [[nodiscard]] static float allowance(int level, int n);
  /// Records one task's level and times; updates the prices and picks the next task's level.
  void record(int task_level, std::size_t receivers, double mask_time_ns, std::uint64_t units, double ray_time_ns,
              std::uint64_t rays_cast);
};

/// Masks of `receivers` (in their order) by the auto method; `embree` must be the scene the BVH
/// was built from. `controllers`, one per thread, carry the cost model across calls
/// (HybridControllers below). With `stats`, adds the work counters and the rays decided by each
/// side. Multithreaded with TBB, tasks of up to 64 neighbouring receivers.
class HybridControllers;
[[nodiscard]] MaskSet hybrid_occlusion(const Bvh& bvh, const lut::MaskEngine& engine, const EmbreeScene& embree,
                                       std::span<const Receiver> receivers, HybridPolicy policy,
                                       HybridControllers& controllers, const ProgressCallback& progress = {},
                                       TraversalStats* stats = nullptr);

/// The mask of one receiver by the auto method, on the calling thread, into `words`
/// (mask_words of N): for the single-point API. Uses the calling thread's controller's price.
void hybrid_mask_one(const Bvh& bvh, const lut::MaskEngine& engine, const EmbreeScene& embree, const Receiver& receiver,
                     HybridPolicy policy, HybridControllers& controllers, std::span<std::uint64_t> words);

/// One HybridController per thread, kept by an engine across calls (opaque: TBB's storage).
class HybridControllers {
 public:
  HybridControllers();
  ~HybridControllers();
  HybridControllers(const HybridControllers&) = delete;
  HybridControllers& operator=(const HybridControllers&) = delete;
  [[nodiscard]] HybridController& local();

 private:
  struct Storage;
  Storage* storage_;
};

}  // namespace exao::bvh
