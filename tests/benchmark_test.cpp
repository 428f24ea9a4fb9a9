// The library's bench loop (bench/): the plan's checks name the option and its value, the rows of
// a plan, and a tiny run on the built-in plane pair that times every row on the same receivers.

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "bench/plan.h"
#include "bench/run.h"
#include "core/builtin_scenes.h"
#include "core/camera.h"
#include "core/check.h"

namespace exao {
namespace {

bench::Plan small_plan() {
  bench::Plan plan;
  plan.samples = {32};
  plan.radii = {{{5.0f, true}, "5%"}};
  plan.methods = {engine::Method::Bvh, engine::Method::Brute};
  plan.masks = {lut::MaskMode::Exact};
  plan.isas = {Isa::Scalar};
  return plan;
}

std::string error_of(const Result<bench::Plan>& plan) { return plan ? std::string("(accepted)") : plan.error().message; }

TEST(BenchPlan, RefusesBadValuesNamingTheOptionAndTheValue) {
  bench::Plan plan = small_plan();
  plan.repeats = 0;
  EXPECT_EQ(error_of(bench::check_plan(plan)), "repeats: must be at least 1, got 0");

  plan = small_plan();
  plan.samples = {32, 33};
  EXPECT_EQ(error_of(bench::check_plan(plan)).rfind("samples: ", 0), 0u);
  EXPECT_NE(error_of(bench::check_plan(plan)).find("33"), std::string::npos);

  plan = small_plan();
  plan.embree_rays.clear();
  EXPECT_EQ(error_of(bench::check_plan(plan)), "embree.rays: give at least one mode");

  plan = small_plan();
  plan.isas.clear();
  EXPECT_EQ(error_of(bench::check_plan(plan)), "isa: give at least one instruction set");

  // raster draws a camera's G-buffer: it serves no bake's receivers.
  plan = small_plan();
  plan.methods.push_back(engine::Method::Raster);
  plan.bake = bake::BakeOptions{};
  EXPECT_EQ(error_of(bench::check_plan(plan)).rfind("method: raster", 0), 0u) << error_of(bench::check_plan(plan));

  plan = small_plan();
  plan.shard = engine::Shard{0, 2};
  EXPECT_EQ(error_of(bench::check_plan(plan)).rfind("shard: ", 0), 0u);

  // No error message names a flag of the exao program.
  plan = small_plan();
  plan.repeats = -3;
  EXPECT_EQ(error_of(bench::check_plan(plan)).find("--"), std::string::npos);
}

TEST(BenchPlan, PutsEmbreeFirstOnceAndResolvesEveryInstructionSet) {
  bench::Plan plan = small_plan();
  plan.methods = {engine::Method::Bvh, engine::Method::Embree, engine::Method::Bvh, engine::Method::Auto};
  plan.masks = {lut::MaskMode::Lut, lut::MaskMode::Exact};
  plan.embree_rays = {EmbreeRays::Packet16, EmbreeRays::Single};
  plan.isas = {std::nullopt, Isa::Scalar};
  plan.lods = {raster::LodOptions{}};  // dropped: no raster row to take a level of detail
  const Result<bench::Plan> checked = bench::check_plan(plan);
  ASSERT_TRUE(checked) << checked.error().message;
  EXPECT_EQ(checked->methods, (std::vector<engine::Method>{engine::Method::Embree, engine::Method::Bvh, engine::Method::Auto}));
  for (const std::optional<Isa>& isa : checked->isas) EXPECT_TRUE(isa.has_value());
  EXPECT_TRUE(checked->lods.empty());

  // Embree per ray mode, then bvh per mask mode and instruction set, then auto exact only.
  const std::vector<bench::Config> rows = bench::configurations(*checked);
  ASSERT_EQ(rows.size(), 2u + 2u * 2u + 2u);
  EXPECT_EQ(rows[0].method, engine::Method::Embree);
  EXPECT_EQ(rows[0].rays, EmbreeRays::Packet16);
  EXPECT_EQ(rows[1].rays, EmbreeRays::Single);
  for (std::size_t r = 2; r < 6; ++r) EXPECT_EQ(rows[r].method, engine::Method::Bvh);
  for (std::size_t r = 6; r < rows.size(); ++r) {
    EXPECT_EQ(rows[r].method, engine::Method::Auto);
    EXPECT_EQ(rows[r].mode, lut::MaskMode::Exact);
  }
}

bench::Workload plane_pair_workload() {
  bench::Workload workload;
  workload.name = "plane-pair";
  Result<Scene> scene = builtin_scene("plane-pair");
  EXAO_CHECK(scene.has_value());
  workload.scene = std::move(*scene);
  workload.width = 16;
  workload.height = 12;
  workload.camera = frame_bounds(workload.scene.bounds(), 16.0f / 12.0f);
  return workload;
}

TEST(BenchRun, TimesEveryRowOnTheSameReceiversAndRays) {
  bench::Plan plan = small_plan();
  plan.repeats = 2;
  plan.label = "tiny";
  const Result<bench::Plan> checked = bench::check_plan(plan);
  ASSERT_TRUE(checked) << checked.error().message;
  bench::Workload workload = plane_pair_workload();
  const Result<bench::Setup> setup = bench::prepare(*checked, workload);
  ASSERT_TRUE(setup) << setup.error().message;
  ASSERT_TRUE(bench::check_receivers(*checked, workload, *setup));
  const std::size_t receivers = setup->receivers.receivers.size();
  ASSERT_GT(receivers, 0u);

  int radius_notes = 0;
  std::vector<std::string> started;
  std::size_t finished = 0;
  std::vector<std::size_t> row_receivers;
  bench::Events events;
  events.radius_ready = [&](const engine::Engine&) { ++radius_notes; };
  events.progress_started = [&](const std::string& label) {
    started.push_back(label);
    return ProgressCallback{};
  };
  events.progress_finished = [&] { ++finished; };
  events.row = [&](const bench::Run& run, const MaskSet& masks) -> Result<void> {
    EXPECT_EQ(masks.samples(), run.samples);
    row_receivers.push_back(masks.size());
    return {};
  };
  const Result<bench::Report> report = bench::run(*checked, workload, *setup, events);
  ASSERT_TRUE(report) << report.error().message;

  EXPECT_EQ(report->label, "tiny");
  EXPECT_EQ(report->scene, "plane-pair");
  EXPECT_EQ(report->receivers, receivers);
  EXPECT_EQ(report->width, 16);
  EXPECT_EQ(report->height, 12);
  EXPECT_EQ(radius_notes, 1);
  EXPECT_EQ(started.size(), 3u * 2u);  // every row, every repeat
  EXPECT_EQ(finished, started.size());
  EXPECT_EQ(row_receivers, std::vector<std::size_t>(3, receivers));

  ASSERT_EQ(report->runs.size(), 3u);
  const std::vector<std::string> methods{"embree", "bvh", "brute"};
  for (std::size_t r = 0; r < report->runs.size(); ++r) {
    const bench::Run& run = report->runs[r];
    SCOPED_TRACE(run.method);
    EXPECT_EQ(run.method, methods[r]);
    EXPECT_EQ(run.samples, 32);
    EXPECT_EQ(run.radius_text, "5%");
    EXPECT_GT(run.radius, 0.0f);
    EXPECT_GT(run.seconds, 0.0);
    // The rays counted: every receiver's N rays, in the time the row took.
    const double rays = static_cast<double>(receivers) * 32.0;
    EXPECT_NEAR(run.mrays_per_s * 1e6 * run.seconds, rays, 1e-6 * rays);
    EXPECT_DOUBLE_EQ(run.speedup_vs_embree, report->runs[0].seconds / run.seconds);
    EXPECT_EQ(run.masks, r == 0 ? "packet16" : "exact");
    EXPECT_EQ(run.isa, r == 0 ? "" : "scalar");
    // Exact masks are Embree's answer on this scene (nothing grazes).
    EXPECT_DOUBLE_EQ(run.ray_agreement, 1.0);
    EXPECT_DOUBLE_EQ(run.identical_receivers, 1.0);
    EXPECT_DOUBLE_EQ(run.max_abs_error, 0.0);
  }
}

TEST(BenchRun, AShardWithNoReceiversIsRefusedNamingTheShard) {
  bench::Plan plan = small_plan();
  plan.bake = bake::BakeOptions{};  // vertices
  plan.shard = engine::Shard{0, 2}; // one chunk of receivers: part 0 of 2 holds none
  const Result<bench::Plan> checked = bench::check_plan(plan);
  ASSERT_TRUE(checked) << checked.error().message;
  bench::Workload workload = plane_pair_workload();
  Result<bake::Document> document = bench::open_document("plane-pair", *checked->bake);
  ASSERT_TRUE(document) << document.error().message;
  workload.document = std::move(*document);
  workload.scene = workload.document->scene();
  const Result<bench::Setup> setup = bench::prepare(*checked, workload);
  ASSERT_TRUE(setup) << setup.error().message;
  EXPECT_GT(setup->all_receivers, 0u);
  EXPECT_TRUE(setup->receivers.receivers.empty());
  const Result<bench::Report> report = bench::run(*checked, workload, *setup);
  ASSERT_FALSE(report);
  EXPECT_EQ(report.error().message.rfind("shard: part 0 of 2 has no receivers (", 0), 0u) << report.error().message;
}

}  // namespace
}  // namespace exao
