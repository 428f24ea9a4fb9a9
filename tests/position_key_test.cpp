// core/position_key.h: the one key every weld by position uses. -0.0 and +0.0 are one point:
// equal keys and equal hashes (hashing raw float bits while comparing with == would break
// unordered_map's contract), so vertices there weld; other positions keep their own keys.

#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include <glm/glm.hpp>

#include "bake/corner_normals.h"
#include "core/position_key.h"

namespace exao {
namespace {

TEST(PositionKey, NegativeAndPositiveZeroHaveOneKeyAndOneHash) {
  const glm::vec3 plus(0.0f, 1.0f, 0.0f);
  const glm::vec3 minus(-0.0f, 1.0f, -0.0f);
  ASSERT_TRUE(std::signbit(minus.x));
  EXPECT_EQ(position_key(plus), position_key(minus));
  EXPECT_EQ(PositionKeyHash{}(position_key(plus)), PositionKeyHash{}(position_key(minus)));
}

TEST(PositionKey, OtherPositionsKeepTheirOwnKeys) {
  const std::array<glm::vec3, 4> points{glm::vec3(0.0f), glm::vec3(1e-38f, 0.0f, 0.0f), glm::vec3(0.0f, -1.0f, 0.0f),
                                        glm::vec3(0.0f, 0.0f, 1.0f)};
  for (std::size_t i = 0; i < points.size(); ++i) {
    for (std::size_t j = i + 1; j < points.size(); ++j) EXPECT_NE(position_key(points[i]), position_key(points[j]));
  }
}

TEST(PositionKey, VerticesAtSignedZerosWeld) {
  std::unordered_map<PositionKey, std::uint32_t, PositionKeyHash> weld;
  const std::vector<glm::vec3> vertices{{0.0f, 0.0f, 0.0f}, {-0.0f, 0.0f, 0.0f}, {0.0f, -0.0f, -0.0f}, {1.0f, 0.0f, 0.0f}};
  std::vector<std::uint32_t> ids;
  for (const glm::vec3& v : vertices) ids.push_back(weld.try_emplace(position_key(v), static_cast<std::uint32_t>(weld.size())).first->second);
  EXPECT_EQ(weld.size(), 2u);
  EXPECT_EQ(ids, (std::vector<std::uint32_t>{0, 0, 0, 1}));
}

// The bake's corner normals smooth across triangles meeting at one position: two triangles 30
// degrees apart (within the crease angle) sharing the corner at the origin give it the same
// normal whether one of them writes that corner as -0.0.
TEST(PositionKey, CornerNormalsSmoothAcrossSignedZeros) {
  const float s = 0.5f, c = 0.8660254f;  // sin and cos of 30 degrees
  const auto normals_with = [&](float zero) {
    const std::vector<glm::vec3> corners{{0.0f, 0.0f, 0.0f}, {1.0f, 0.0f, 0.0f},  {0.0f, 0.0f, -1.0f},
                                         {zero, 0.0f, 0.0f}, {0.0f, 0.0f, -1.0f}, {-c, s, 0.0f}};
    return bake::corner_normals(corners, bake::kCreaseDegrees);
  };
  const std::vector<glm::vec3> plus = normals_with(0.0f);
  const std::vector<glm::vec3> minus = normals_with(-0.0f);
  // Welded: the shared corner's normal leans between the two faces, unlike the first triangle's own (+Y).
  EXPECT_GT(glm::length(plus[0] - glm::vec3(0.0f, 1.0f, 0.0f)), 1e-3f);
  EXPECT_EQ(minus[0], plus[0]);
  EXPECT_EQ(minus[3], plus[3]);
}

}  // namespace
}  // namespace exao
