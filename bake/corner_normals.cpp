#include "bake/corner_normals.h"

#include <cmath>
#include <unordered_map>

#include "core/position_key.h"

namespace exao::bake {
namespace {

glm::dvec3 area_normal(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) {
  return glm::cross(glm::dvec3(b) - glm::dvec3(a), glm::dvec3(c) - glm::dvec3(a));
}

glm::vec3 unit_or_zero(const glm::dvec3& n) {
  const double length = glm::length(n);
  return length > 0.0 && std::isfinite(length) ? glm::vec3(n / length) : glm::vec3(0.0f);
}

}  // namespace

std::vector<glm::vec3> vertex_normals(std::span<const glm::vec3> positions, std::span<const std::uint32_t> corners,
                                      bool two_sided) {
  std::vector<glm::dvec3> sum(positions.size(), glm::dvec3(0.0));
  for (std::size_t t = 0; t + 2 < corners.size(); t += 3) {
    const glm::dvec3 n = area_normal(positions[corners[t]], positions[corners[t + 1]], positions[corners[t + 2]]);
    for (std::size_t k = 0; k < 3; ++k) {
      glm::dvec3& s = sum[corners[t + k]];
      s += two_sided && glm::dot(s, n) < 0.0 ? -n : n;
    }
  }
  std::vector<glm::vec3> out(positions.size());
  for (std::size_t v = 0; v < positions.size(); ++v) out[v] = unit_or_zero(sum[v]);
  return out;
}

std::vector<glm::vec3> corner_normals(std::span<const glm::vec3> corner_positions, float crease_degrees) {
  const std::size_t triangles = corner_positions.size() / 3;
  std::vector<glm::dvec3> face(triangles);
  for (std::size_t t = 0; t < triangles; ++t) {
    face[t] = area_normal(corner_positions[3 * t], corner_positions[3 * t + 1], corner_positions[3 * t + 2]);
  }
  // Corners grouped by position: each group lists the triangles that meet there.
  std::unordered_map<PositionKey, std::vector<std::uint32_t>, PositionKeyHash> at;
  at.reserve(corner_positions.size());
  for (std::size_t c = 0; c < corner_positions.size(); ++c) {
    at[position_key(corner_positions[c])].push_back(static_cast<std::uint32_t>(c / 3));
  }
  const double min_cos = std::cos(static_cast<double>(crease_degrees) * 3.14159265358979323846 / 180.0);
  std::vector<glm::vec3> out(corner_positions.size(), glm::vec3(0.0f));
  for (std::size_t c = 0; c < corner_positions.size(); ++c) {
    const glm::dvec3 own = face[c / 3];
    const double own_length = glm::length(own);
    if (!(own_length > 0.0)) continue;
    glm::dvec3 sum(0.0);
    for (const std::uint32_t t : at[position_key(corner_positions[c])]) {
      const double length = glm::length(face[t]);
      if (length > 0.0 && glm::dot(face[t], own) >= min_cos * length * own_length) sum += face[t];
    }
    out[c] = unit_or_zero(sum);
  }
  return out;
}

}  // namespace exao::bake
