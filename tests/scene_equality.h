#pragma once
// The loader tests' check that a fast path gives the scene CGAL's reader gives, bit for bit.

#include <gtest/gtest.h>

#include <cstring>
#include <optional>
#include <string>

#include "core/error.h"
#include "core/scene.h"
#include "io/polygon_soup_loader.h"
#include "tests/test_support.h"

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

// The same scene, or the same error message.
inline void expect_same_result(const Result<Scene>& got, const Result<Scene>& want) {
  ASSERT_EQ(got.has_value(), want.has_value()) << (got ? want.error().message : got.error().message);
  if (!want) {
    EXPECT_EQ(got.error().message, want.error().message);
    return;
  }
  expect_same_scene(*got, *want);
}

// Writes `text` to dir/name and loads it by CGAL's path, by the loader's choice and by the fast
// reader `read_fast` (text -> optional Result<Scene>, nullopt: left to CGAL): the three must
// agree. Returns whether the fast reader took the file.
template <class ReadFast>
bool expect_fast_path_as_cgal(const TempDir& dir, const std::string& name, const std::string& text,
                              ReadFast&& read_fast) {
  const std::string path = (dir / name).string();
  write_file(path, text);
  const Result<Scene> cgal = load_polygon_soup(path, {}, SoupPath::Cgal);
  const Result<Scene> fast = load_polygon_soup(path);
  expect_same_result(fast, cgal);
  const std::optional<Result<Scene>> direct = read_fast(text);
  if (direct && cgal) {
    EXPECT_TRUE(direct->has_value());
    if (direct->has_value()) expect_same_scene(**direct, *cgal);
  }
  if (direct && !cgal) {
    EXPECT_FALSE(direct->has_value()) << "the fast path loaded what CGAL refuses";
  }
  return direct.has_value();
}

}  // namespace exao::test
