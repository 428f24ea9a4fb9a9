// The auto method's cost model (bvh/hybrid.h): which allowance level each task gets, given what
// the levels cost. The answer never depends on it (auto_test); this is about not wasting time.

#include <gtest/gtest.h>

#include <array>

#include "bvh/hybrid.h"

namespace exao::bvh {
namespace {

// Runs `tasks` tasks of 64 receivers in which level l costs cost[l] ns per receiver; returns
// how many tasks each level got.
std::array<int, HybridController::kLevels> run_tasks(HybridController& controller, const double (&cost)[5], int tasks) {
  std::array<int, HybridController::kLevels> got{};
  for (int t = 0; t < tasks; ++t) {
    const int level = controller.level;
    ++got[level];
    // All of the time in the Embree phase at level 0, in masks elsewhere (prices do not matter).
    const double total = cost[level] * 64;
    controller.record(level, 64, level == 0 ? 0.0 : total, level == 0 ? 0 : 1000, level == 0 ? total : 0.0, 64 * 128);
  }
  return got;
}

TEST(HybridController, TriesEveryLevelOnceThenFollowsTheCheapest) {
  HybridController controller;
  const double cost[5] = {300.0, 500.0, 800.0, 1200.0, 2500.0};
  const auto got = run_tasks(controller, cost, 5);
  for (int l = 0; l < HybridController::kLevels; ++l) EXPECT_EQ(got[l], 1) << "level " << l;
  EXPECT_EQ(controller.level, 0);
}

TEST(HybridController, ExploresLessOftenWhileTheNeighbourLoses) {
  // Rays alone win by far (a dense bake): after the first tries, a neighbour gets a task at
  // doubling intervals, so over 4000 tasks the worse levels get far fewer than every 16th.
  HybridController controller;
  const double cost[5] = {300.0, 500.0, 800.0, 1200.0, 2500.0};
  const auto got = run_tasks(controller, cost, 4000);
  const int elsewhere = 4000 - got[0];
  EXPECT_GT(elsewhere, 4) << "it must keep trying the neighbour now and then";
  EXPECT_LT(elsewhere, 4000 / 64) << "a fixed period of 16 would give " << 4000 / 16;
}

TEST(HybridController, NoticesWhenTheNeighbourBecomesCheaper) {
  HybridController controller;
  const double before[5] = {300.0, 500.0, 800.0, 1200.0, 2500.0};
  run_tasks(controller, before, 4000);  // the interval has grown to its maximum
  // The geometry changes: masks with allowance N/16 now pay.
  const double after[5] = {300.0, 150.0, 800.0, 1200.0, 2500.0};
  int tasks = 0;
  // (Level 1 as the best, not as the neighbour a task tries.)
  while (!(controller.level == 1 && controller.explored_from < 0) && tasks < 10000) {
    run_tasks(controller, after, 1);
    ++tasks;
  }
  // One interval at most to look again, then the running average needs a few cheaper tasks,
  // each after the shortest interval.
  EXPECT_LE(tasks, static_cast<int>(HybridController::kMaxExplorePeriod + 4 * HybridController::kExplorePeriod));
  // ... and then stays there.
  const auto got = run_tasks(controller, after, 200);
  EXPECT_GT(got[1], 180);
}

}  // namespace
}  // namespace exao::bvh
