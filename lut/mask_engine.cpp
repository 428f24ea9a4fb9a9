#include "lut/mask_engine.h"

#include <cmath>
#include <utility>

#include "core/surface_rule.h"

namespace exao::lut {

const char* mask_mode_name(MaskMode mode) { return name_of(mode); }

Result<MaskMode> parse_mask_mode(const std::string& name) {
  if (const std::optional<MaskMode> m = parse_enum<MaskMode>(name)) return *m;
  return fail("masks: unknown mask mode '" + name + "' (" + name_list<MaskMode>() + ")");
}

MaskEngine& MaskEngine::operator=(MaskEngine&& o) noexcept {
  if (this == &o) return *this;
  rays_ = std::move(o.rays_);
  mode_ = o.mode_;
  samples_ = std::move(o.samples_);
  table_ = std::move(o.table_);
  kernels_ = o.kernels_;
  context_ = o.context_;
  bind();
  return *this;
}

void MaskEngine::bind() {
  context_.samples = &samples_;
  context_.table = table_ ? &*table_ : nullptr;
  context_.radius = rays_.radius;
  context_.inv_radius = 1.0f / rays_.radius;
  context_.exact = mode_ == MaskMode::Exact;
}

Result<MaskEngine> MaskEngine::build(const ShadowRays& rays, MaskMode mode, int resolution, std::optional<Isa> isa) {
  if (auto ok = check_sample_count(rays.count()); !ok) return std::unexpected(ok.error());
  if (!(std::isfinite(rays.radius) && rays.radius > 0.0f)) return fail("radius: must be a finite length > 0, got " + std::to_string(rays.radius));
  const Result<Isa> level = resolve_isa(isa);
  if (!level) return std::unexpected(level.error());
  MaskEngine engine;
  engine.rays_ = rays;
  engine.mode_ = mode;
  engine.samples_ = SampleArrays(rays.pattern);
  engine.kernels_ = &mask_kernels(*level);
  if (mode == MaskMode::Lut) {
    auto table = PlaneTable::build(rays.pattern, TableKind::Points, resolution);
    if (!table) return std::unexpected(table.error());
    engine.table_ = std::move(*table);
  }
  engine.bind();
  return engine;
}

Result<MaskEngine> MaskEngine::with_table(const ShadowRays& rays, PlaneTable table, std::optional<Isa> isa) {
  if (table.kind() != TableKind::Points || table.samples() != rays.count() ||
      table.pattern_hash() != lut::pattern_hash(rays.pattern)) {
    return fail("plane table: built for another sample pattern or kind than these rays");
  }
  auto engine = build(rays, MaskMode::Exact, 0, isa);
  if (!engine) return engine;
  engine->mode_ = MaskMode::Lut;
  engine->table_ = std::move(table);
  engine->bind();
  return engine;
}

}  // namespace exao::lut
