#pragma once
// The AO of the bake tests: the default backend (bvh) through the library engine, as `exao bake`
// runs it.

#include <gtest/gtest.h>

#include <span>
#include <vector>

#include "core/scene.h"
#include "engine/engine.h"

namespace exao::test {

struct BvhAo {
  engine::Engine engine;

  BvhAo(const Scene& scene, float radius, int samples, lut::MaskMode mode = lut::MaskMode::Lut)
      : engine(build(scene, radius, samples, mode)) {}
  static engine::Engine build(const Scene& scene, float radius, int samples, lut::MaskMode mode) {
    engine::Options options;
    options.method = engine::Method::Bvh;
    options.radius = {radius, false};
    options.samples = samples;
    options.masks = mode;
    Result<engine::Engine> built = engine::Engine::build(scene, options, engine::Receivers::Points);
    EXPECT_TRUE(built) << built.error().message;
    return std::move(*built);
  }
  std::vector<float> operator()(std::span<const Receiver> receivers) const { return *engine.ao(receivers); }
  const engine::Engine& function() const { return engine; }
};

}  // namespace exao::test
