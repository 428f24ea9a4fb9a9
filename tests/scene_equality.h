#pragma once
// The loader tests' check that a fast path gives the scene CGAL's reader gives, bit for bit.

#include <gtest/gtest.h>

#include <cstring>

#include "core/scene.h"

namespace exao::test {

inline void expect_same_scene(const Scene& got, const Scene& want) {
  ASSERT_EQ(got.triangle_count(), want.triangle_count());
  ASSERT_EQ(got.vertices.size(), want.vertices.size());
  for (std::size_t i = 0; i < got.vertices.size(); ++i) {
    ASSERT_EQ(std::memcmp(&got.vertices[i], &want.vertices[i], sizeof(glm::vec3)), 0) << "vertex " << i;
  }
  EXPECT_EQ(got.two_sided, want.two_sided);
  EXPECT_EQ(got.material, want.material);
  EXPECT_EQ(got.report.triangles_read, want.report.triangles_read);
  EXPECT_EQ(got.report.zero_area_skipped, want.report.zero_area_skipped);
  EXPECT_EQ(got.report.non_finite_skipped, want.report.non_finite_skipped);
  EXPECT_EQ(got.report.notes, want.report.notes);
}

}  // namespace exao::test
