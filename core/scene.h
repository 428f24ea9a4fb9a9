#pragma once
// A scene is a soup of world-space triangles, each with its sidedness and material.

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "core/bounds.h"
#include "core/camera.h"
#include "core/coordinate_limit.h"

namespace exao {

struct Cutouts;  // core/cutouts.h

/// What a loader read and what it left out, so the caller can say so.
struct LoadReport {
  std::size_t triangles_read = 0;       // every triangle in the file, before any was skipped
  std::size_t zero_area_skipped = 0;    // exactly zero area: they block no ray
  std::size_t non_finite_skipped = 0;   // a NaN, infinite or huge (beyond +-1e17) vertex
  std::size_t primitives_skipped = 0;   // points and lines (glTF modes 0-3)
  std::vector<std::string> notes;       // one line each, for the user
};

struct Scene {
  /// Spare vertices of capacity (not of size) that loaders reserve after `vertices`, so that
  /// Embree may read the array in place with its 16-byte loads (EmbreeScene::build_sharing)
  /// instead of copying it.
  static constexpr std::size_t kVertexPadding = 2;

  std::string name;
  /// Three vertices per triangle, world space. The front face is counter-clockwise
  /// (glTF): its normal is cross(v1 - v0, v2 - v0).
  std::vector<glm::vec3> vertices;
  std::vector<std::uint8_t> two_sided;  // per triangle: 1 blocks from both sides
  std::vector<std::int32_t> material;   // per triangle: material index, -1 when none
  /// Per triangle, or empty (every triangle object 0): the object it belongs to (the public
  /// API's mesh or instance index), which a receiver can exclude (Receiver::excluded_object).
  /// Never kNoObject.
  std::vector<std::uint32_t> object;
  std::vector<Camera> cameras;          // cameras the file defines, in file order
  /// Per material index: opacity in [0, 1] for methods that weigh occluders by it (A-buffer AO,
  /// seed 004). glTF: BLEND is baseColorFactor's alpha, MASK is 1 when that alpha reaches
  /// alphaCutoff and 0 otherwise, OPAQUE is 1 (textures are not read). Empty, or an index
  /// beyond it, means opaque. Exact AO ignores it: every triangle blocks.
  std::vector<float> material_opacity;
  /// Alpha-tested triangles (glTF alphaMode MASK, and BLEND per core/cutouts.h's policy) and
  /// what decides them; nullptr: every triangle opaque. Shared: copies of a scene share the
  /// textures. Indexed by triangle, so whoever reorders or drops triangles must drop it.
  std::shared_ptr<const Cutouts> cutouts;
  LoadReport report;
  /// The last `ground_triangles` triangles are an added ground plane (core/ground_plane.h):
  /// occluders like any other, left out of bounds() so that "5% of the diagonal" and camera
  /// framing still mean the model's.
  std::size_t ground_triangles = 0;

  [[nodiscard]] std::size_t triangle_count() const { return two_sided.size(); }
  [[nodiscard]] std::array<glm::vec3, 3> triangle(std::size_t i) const {
    return {vertices[3 * i], vertices[3 * i + 1], vertices[3 * i + 2]};
  }
  /// Bounds of the triangles, the ground plane excepted.
  [[nodiscard]] Bounds bounds() const;
  /// Opacity of triangle i's material (material_opacity), 1 when it has none.
  [[nodiscard]] float opacity(std::size_t i) const {
    const std::int32_t m = material[i];
    return m >= 0 && static_cast<std::size_t>(m) < material_opacity.size() ? material_opacity[static_cast<std::size_t>(m)] : 1.0f;
  }

  /// Room for `triangles` more without reallocation (and Embree's padding after the vertices),
  /// on huge pages where the kernel has them (core/huge_pages.h): what a loader calls once it
  /// knows the count.
  void reserve(std::size_t triangles);
  /// Adds a triangle unless it has a non-finite vertex (or one beyond kMaxCoordinate,
  /// core/coordinate_limit.h) or exactly zero area; either case is
  /// counted in `report`. Returns whether it was added.
  bool add_triangle(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c, bool is_two_sided,
                    std::int32_t material_index) {
    ++report.triangles_read;
    // Beyond the limit is as unusable as infinite: Embree would abort on rays from there.
    if (!within_coordinate_limit(a) || !within_coordinate_limit(b) || !within_coordinate_limit(c)) {
      ++report.non_finite_skipped;
      return false;
    }
    // Double precision, so that only truly degenerate triangles (repeated or collinear
    // vertices) are dropped, not merely small ones.
    const glm::dvec3 n = glm::cross(glm::dvec3(b) - glm::dvec3(a), glm::dvec3(c) - glm::dvec3(a));
    if (n == glm::dvec3(0.0)) {
      ++report.zero_area_skipped;
      return false;
    }
    vertices.push_back(a);
    vertices.push_back(b);
    vertices.push_back(c);
    two_sided.push_back(is_two_sided ? 1 : 0);
    material.push_back(material_index);
    return true;
  }
};

enum class Sidedness { Auto, One, Two };

/// Overrides every triangle's sidedness (Auto keeps what the file says).
void apply_sidedness(Scene& scene, Sidedness sidedness);

[[nodiscard]] std::size_t two_sided_count(const Scene& scene);

}  // namespace exao
