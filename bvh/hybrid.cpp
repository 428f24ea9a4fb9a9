#include "bvh/hybrid.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/combinable.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "core/check.h"
#include "lut/float_mode.h"

namespace exao::bvh {

struct HybridControllers::Storage {
  tbb::enumerable_thread_specific<HybridController> local;
};

HybridControllers::HybridControllers() : storage_(new Storage) {}
HybridControllers::~HybridControllers() { delete storage_; }
HybridController& HybridControllers::local() { return storage_->local.local(); }

const char* hybrid_policy_name(HybridPolicy policy) { return name_of(policy); }

Result<HybridPolicy> parse_hybrid_policy(const std::string& name) {
  if (const std::optional<HybridPolicy> p = parse_enum<HybridPolicy>(name)) return *p;
  return fail("hybrid: unknown policy '" + name + "' (" + name_list<HybridPolicy>() + ")");
}

float HybridController::allowance(int level, int n) {
  switch (level) {
    case 0: return 0.0f;
    case 1: return static_cast<float>(n) / 16.0f;
    case 2: return static_cast<float>(n) / 4.0f;
    case 3: return static_cast<float>(n);
    default: return std::numeric_limits<float>::infinity();
  }
}

void HybridController::record(int task_level, std::size_t receivers, double mask_time_ns, std::uint64_t units,
                              double ray_time_ns, std::uint64_t rays_cast) {
  mask_ns = 0.9 * mask_ns + mask_time_ns;
  mask_units = 0.9 * mask_units + static_cast<double>(units);
  ray_ns = 0.9 * ray_ns + ray_time_ns;
  rays = 0.9 * rays + static_cast<double>(rays_cast);
  if (mask_units > 0.0 && rays > 0.0 && ray_ns > 0.0) {
    rays_per_unit = static_cast<float>(std::clamp((mask_ns / mask_units) / (ray_ns / rays), 1e-3, 1e3));
  }
  const double per_receiver = (mask_time_ns + ray_time_ns) / static_cast<double>(receivers);
  double& average = cost[task_level];
  average = average == 0.0 ? per_receiver : 0.75 * average + 0.25 * per_receiver;
  ++tasks;
  // Every level once first (a thread's first five tasks), cheapest first is not known yet.
  for (int l = 0; l < kLevels; ++l) {
    if (cost[l] == 0.0) {
      level = l;
      return;
    }
  }
  int best = 0;
  for (int l = 1; l < kLevels; ++l) {
    if (cost[l] < cost[best]) best = l;
  }
  if (explored_from >= 0) {
    // The running average moves a quarter of the way a task, so judge the neighbour by this
    // task alone: cheaper than the best's average, look again soon.
    const bool promising = per_receiver < cost[explored_from];
    explore_period = promising ? kExplorePeriod : std::min(2 * explore_period, kMaxExplorePeriod);
    next_explore = tasks + explore_period;
    explored_from = -1;
  }
  level = best;
  if (tasks >= next_explore) {
    ++explorations;
    const int step = explorations % 2 == 0 ? 1 : -1;
    level = best + step >= 0 && best + step < kLevels ? best + step : best - step;
    explored_from = best;
  }
}

namespace {

using Clock = std::chrono::steady_clock;

// Receivers per measured task: a multiple of Embree's packet width, and long enough (tens of
// microseconds at least) that the clock's resolution does not matter.
constexpr std::size_t kTask = 64;

double nanoseconds(Clock::time_point a, Clock::time_point b) {
  return static_cast<double>(std::chrono::duration_cast<std::chrono::nanoseconds>(b - a).count());
}


template <int Bits, bool Stats>
void run_task(const Bvh& bvh, const lut::MaskEngine& engine, const EmbreeScene& embree,
              std::span<const Receiver> receivers, std::size_t begin, std::size_t end, HybridPolicy policy,
              HybridController& controller, std::span<std::uint64_t> out, TraversalStats* stats) {
  // out: the masks of receivers [begin, end), mask_words of N words each.
  const int n = engine.samples();
  const std::size_t words = static_cast<std::size_t>(n + 63) / 64;
  const std::size_t count = end - begin;
  Frame frames[kTask];
  std::uint64_t undecided[kTask * (Bits / 64)];
  const int level = policy == HybridPolicy::Masks ? HybridController::kUnbounded : controller.level;
  const MaskBudget budget{controller.rays_per_unit, HybridController::allowance(level, n)};
  const MaskBudget* limit = level == HybridController::kUnbounded ? nullptr : &budget;
  const Mask<Bits> all = engine.template all_rays<Bits>();

  const Clock::time_point t0 = Clock::now();
  std::uint64_t units = 0;
  OccluderCache cache;  // the task's receivers are neighbours: they share occluders
  for (std::size_t i = 0; i < count; ++i) {
    frames[i] = engine.rays().frame(receivers[begin + i]);
    std::span<std::uint64_t> row_undecided(undecided + i * words, words);
    if (policy == HybridPolicy::Rays) {
      store(all, row_undecided);
      continue;
    }
    HybridOutcome<Bits> outcome;
    const Mask<Bits> sure = traverse_certain<Bits, Stats>(bvh, engine, frames[i], stats, limit, outcome, &cache);
    store(sure, out.subspan(i * words, words));
    store(outcome.undecided, row_undecided);
    units += outcome.units;
    if constexpr (Stats) {
      if (!outcome.complete) ++stats->receivers_stopped;
    }
  }
  const Clock::time_point t1 = Clock::now();
  const std::size_t cast = embree.occlude_selected(
      engine.rays(), std::span<const Frame>(frames, count), std::span<const std::uint64_t>(undecided, count * words),
      words, out);
  const Clock::time_point t2 = Clock::now();
  if (stats) {
    if (policy == HybridPolicy::Rays) stats->receivers += count;
    stats->rays_cast += cast;
    stats->rays += count * static_cast<std::size_t>(n);
  }

  if (policy != HybridPolicy::Adaptive) return;
  controller.record(level, count, nanoseconds(t0, t1), units, nanoseconds(t1, t2), cast);
}

template <int Bits, bool Stats>
void run(const Bvh& bvh, const lut::MaskEngine& engine, const EmbreeScene& embree, std::span<const Receiver> receivers,
         HybridPolicy policy, HybridControllers& controllers, MaskSet& masks, const ProgressCallback& progress,
         TraversalStats* stats) {
  ProgressCounter counter(progress, receivers.size());
  tbb::combinable<TraversalStats> local;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, receivers.size(), kTask),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      const lut::FlushDenormals flush;  // the same float mode as every other backend
                      HybridController& controller = controllers.local();
                      TraversalStats* mine = Stats ? &local.local() : nullptr;
                      for (std::size_t first = range.begin(); first < range.end(); first += kTask) {
                        const std::size_t last = std::min(range.end(), first + kTask);
                        const std::size_t words = static_cast<std::size_t>(masks.words());
                        run_task<Bits, Stats>(bvh, engine, embree, receivers, first, last, policy, controller,
                                              masks.all_rows().subspan(first * words, (last - first) * words), mine);
                      }
                      counter.add(range.size());
                    });
  if (stats) local.combine_each([&](const TraversalStats& s) { *stats += s; });
}

}  // namespace

MaskSet hybrid_occlusion(const Bvh& bvh, const lut::MaskEngine& engine, const EmbreeScene& embree,
                         std::span<const Receiver> receivers, HybridPolicy policy, HybridControllers& controllers,
                         const ProgressCallback& progress, TraversalStats* stats) {
  EXAO_CHECK(engine.mode() == lut::MaskMode::Exact);
  MaskSet masks(receivers.size(), engine.samples());
  with_mask_bits(engine.samples(), [&](auto bits) {
    constexpr int Bits = decltype(bits)::value;
    if (stats) {
      run<Bits, true>(bvh, engine, embree, receivers, policy, controllers, masks, progress, stats);
    } else {
      run<Bits, false>(bvh, engine, embree, receivers, policy, controllers, masks, progress, nullptr);
    }
  });
  return masks;
}

void hybrid_mask_one(const Bvh& bvh, const lut::MaskEngine& engine, const EmbreeScene& embree, const Receiver& receiver,
                     HybridPolicy policy, HybridControllers& controllers, std::span<std::uint64_t> words) {
  // One receiver is a task of one: the thread's level, timed like a task (three clock reads,
  // tens of nanoseconds against microseconds of work), so single-point callers learn too.
  std::fill(words.begin(), words.end(), 0);
  with_mask_bits(engine.samples(), [&](auto bits) {
    constexpr int Bits = decltype(bits)::value;
    const lut::FlushDenormals flush;
    run_task<Bits, false>(bvh, engine, embree, std::span<const Receiver>(&receiver, 1), 0, 1, policy,
                          controllers.local(), words, nullptr);
  });
}

}  // namespace exao::bvh
