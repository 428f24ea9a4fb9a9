#include "bench/plan.h"

#include <algorithm>

#include "core/sample_pattern.h"

namespace exao::bench {

Result<Plan> check_plan(Plan plan) {
  if (plan.repeats < 1) return fail("repeats: must be at least 1, got " + std::to_string(plan.repeats));
  if (plan.shard && !plan.bake) return fail("shard: only with a bake's receivers (vertices or texels, cut into chunks)");
  std::vector<engine::Method> methods{engine::Method::Embree};
  for (const engine::Method m : plan.methods) {
    if (std::find(methods.begin(), methods.end(), m) == methods.end()) methods.push_back(m);
  }
  plan.methods = std::move(methods);
  if (plan.embree_rays.empty()) return fail("embree.rays: give at least one mode");
  for (std::optional<Isa>& isa : plan.isas) {
    Result<Isa> level = resolve_isa(isa);
    if (!level) return std::unexpected(level.error());
    isa = *level;
  }
  if (plan.isas.empty()) return fail("isa: give at least one instruction set");
  if (plan.samples.empty()) return fail("samples: give at least one count");
  for (const int n : plan.samples) {
    if (auto ok = check_sample_count(n); !ok) return std::unexpected(ok.error());
  }
  const engine::Receivers receivers = plan.bake ? engine::Receivers::Points : engine::Receivers::Pixels;
  for (const engine::Method m : plan.methods) {
    for (const lut::MaskMode mode : plan.masks) {
      if (m == engine::Method::Auto && mode != lut::MaskMode::Exact) continue;  // one exact row
      engine::Options o = plan.base;
      o.method = m;
      o.masks = mode;
      if (auto ok = engine::check_serves(o, receivers); !ok) return std::unexpected(ok.error());
    }
  }
  // Levels of detail: one raster+lod row per entry and raster row; none without raster.
  if (std::find(plan.methods.begin(), plan.methods.end(), engine::Method::Raster) == plan.methods.end()) {
    plan.lods.clear();
  }
  for (const raster::LodOptions& lod : plan.lods) {
    engine::Options o = plan.base;
    o.method = engine::Method::Raster;
    o.lod = lod;
    if (auto ok = engine::check_options(o); !ok) return std::unexpected(ok.error());
  }
  return plan;
}

std::vector<Config> configurations(const Plan& plan) {
  std::vector<Config> configs;
  for (const EmbreeRays r : plan.embree_rays) configs.push_back({engine::Method::Embree, lut::MaskMode::Exact, r, std::nullopt});
  for (const engine::Method m : plan.methods) {
    if (m == engine::Method::Embree) continue;
    for (const lut::MaskMode mode : plan.masks) {
      // auto has exact masks only: one row, whatever the plan's masks list.
      if (m == engine::Method::Auto && mode != lut::MaskMode::Exact) continue;
      for (const std::optional<Isa> isa : plan.isas) configs.push_back({m, mode, EmbreeRays::Single, isa});
    }
  }
  for (const lut::MaskMode mode : plan.masks) {
    for (const std::optional<Isa> isa : plan.isas) {
      for (std::size_t l = 0; l < plan.lods.size(); ++l) {
        configs.push_back({engine::Method::Raster, mode, EmbreeRays::Single, isa, static_cast<int>(l)});
      }
    }
  }
  return configs;
}

engine::Options row_options(const Plan& plan, const Config& config, int samples, const engine::Length& radius) {
  engine::Options o = plan.base;
  o.method = config.method;
  if (config.lod >= 0) o.lod = plan.lods[static_cast<std::size_t>(config.lod)];
  o.masks = config.mode;
  o.isa = config.isa;
  o.samples = samples;
  o.radius = radius;
  return o;
}

}  // namespace exao::bench
