#pragma once
// A scene is a soup of world-space triangles, each with its sidedness and material.

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "core/bounds.h"
#include "core/camera.h"

namespace exao {

/// What a loader read and what it left out, so the caller can say so.
struct LoadReport {
  std::size_t triangles_read = 0;       // every triangle in the file, before any was skipped
  std::size_t zero_area_skipped = 0;    // exactly zero area: they block no ray
  std::size_t non_finite_skipped = 0;   // a NaN, infinite or huge (beyond +-1e17) vertex
  std::size_t primitives_skipped = 0;   // points and lines (glTF modes 0-3)
  std::vector<std::string> notes;       // one line each, for the user
};

struct Scene {
  std::string name;
  /// Three vertices per triangle, world space. The front face is counter-clockwise
  /// (glTF): its normal is cross(v1 - v0, v2 - v0).
  std::vector<glm::vec3> vertices;
  std::vector<std::uint8_t> two_sided;  // per triangle: 1 blocks from both sides
  std::vector<std::int32_t> material;   // per triangle: material index, -1 when none
  std::vector<Camera> cameras;          // cameras the file defines, in file order
  LoadReport report;

  [[nodiscard]] std::size_t triangle_count() const { return two_sided.size(); }
  [[nodiscard]] std::array<glm::vec3, 3> triangle(std::size_t i) const {
    return {vertices[3 * i], vertices[3 * i + 1], vertices[3 * i + 2]};
  }
  [[nodiscard]] Bounds bounds() const;

  /// Adds a triangle unless it has a non-finite vertex (or one beyond kMaxCoordinate,
  /// core/coordinate_limit.h) or exactly zero area; either case is
  /// counted in `report`. Returns whether it was added.
  bool add_triangle(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c, bool is_two_sided,
                    std::int32_t material_index);
};

enum class Sidedness { Auto, One, Two };

/// Overrides every triangle's sidedness (Auto keeps what the file says).
void apply_sidedness(Scene& scene, Sidedness sidedness);

[[nodiscard]] std::size_t two_sided_count(const Scene& scene);

}  // namespace exao
