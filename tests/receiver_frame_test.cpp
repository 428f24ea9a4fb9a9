// The receiver frame (DESIGN.md section 3): orthonormal, keyed, and never below the horizon.

#include <gtest/gtest.h>

#include "core/random.h"
#include "core/shadow_rays.h"

namespace exao {
namespace {

glm::vec3 random_unit(Rng& rng) {
  while (true) {
    const glm::vec3 v(2 * rng.uniform() - 1, 2 * rng.uniform() - 1, 2 * rng.uniform() - 1);
    const float l = glm::length(v);
    if (l > 0.1f && l < 1.0f) return v / l;
  }
}

TEST(ReceiverFrame, OrthonormalAndRightHanded) {
  Rng rng(1);
  for (int i = 0; i < 10000; ++i) {
    const Receiver r{glm::vec3(0.0f), random_unit(rng) * 3.0f, rng.next()};
    const Frame f = make_frame(r, 0.0f, 0.2f);
    EXPECT_NEAR(glm::length(f.tangent), 1.0f, 1e-5f);
    EXPECT_NEAR(glm::length(f.bitangent), 1.0f, 1e-5f);
    EXPECT_NEAR(glm::length(f.normal), 1.0f, 1e-5f);
    EXPECT_NEAR(glm::dot(f.tangent, f.bitangent), 0.0f, 1e-5f);
    EXPECT_NEAR(glm::dot(f.tangent, f.normal), 0.0f, 1e-5f);
    EXPECT_NEAR(glm::dot(glm::cross(f.tangent, f.bitangent), f.normal), 1.0f, 1e-5f);
  }
}

TEST(ReceiverFrame, NoRayBelowTheTrueTangentPlane) {
  for (const int n : {32, 128, 1024}) {
    const Result<SamplePattern> pattern = make_sample_pattern(n, Falloff::Constant);
    ASSERT_TRUE(pattern.has_value());
    const ShadowRays rays{*pattern, 1.0f, 0.0f};
    Rng rng(static_cast<std::uint64_t>(n));
    float lowest = 1.0f;
    for (int i = 0; i < 20000; ++i) {
      const Receiver r{glm::vec3(0.0f), random_unit(rng), static_cast<std::uint64_t>(i)};
      const Frame f = rays.frame(r);
      for (const glm::vec3& w : pattern->directions) lowest = std::min(lowest, glm::dot(f.to_world_direction(w), r.normal));
    }
    EXPECT_GT(lowest, 0.0f) << "N = " << n;
  }
}

TEST(ReceiverFrame, SameKeySameFrameOtherKeyOtherFrame) {
  const Receiver a{{1, 2, 3}, {0, 1, 0}, 42};
  Receiver b = a;
  const Frame fa = make_frame(a, 0.01f, 0.1f);
  const Frame fb = make_frame(b, 0.01f, 0.1f);
  EXPECT_EQ(fa.tangent, fb.tangent);
  EXPECT_EQ(fa.normal, fb.normal);
  b.key = 43;
  const Frame fc = make_frame(b, 0.01f, 0.1f);
  EXPECT_NE(fa.tangent, fc.tangent);
  // The tilt stays within its bound and the origin moves along the true normal.
  EXPECT_LE(std::acos(std::min(1.0f, glm::dot(fa.normal, glm::vec3(0, 1, 0)))), 0.1f + 1e-5f);
  EXPECT_NEAR(glm::distance(fa.origin, glm::vec3(1, 2.01f, 3)), 0.0f, 1e-6f);
}

}  // namespace
}  // namespace exao
