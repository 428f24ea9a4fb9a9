#pragma once
// Receiver normals from the geometry itself (--normals geometric).

#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

namespace exao::bake {

/// Per vertex, the area-weighted geometric normal of the triangles that use it: the sum of
/// cross(b - a, c - a) (twice the area times the unit normal) over them, normalised; zero for a
/// vertex no triangle with area uses. `corners` holds three indices into `positions` per
/// triangle, front face counter-clockwise. With `two_sided`, a triangle whose normal points
/// against the sum so far is added flipped: two-sided sheets (OBJ and friends) are often wound
/// inconsistently, and opposite normals would cancel into one that points into the surface.
[[nodiscard]] std::vector<glm::vec3> vertex_normals(std::span<const glm::vec3> positions,
                                                    std::span<const std::uint32_t> corners, bool two_sided = false);

/// Per triangle corner (corner_positions: three per triangle, front face counter-clockwise), the
/// area-weighted normal of every triangle that has a corner at exactly the same position and
/// whose normal is within `crease_degrees` of this corner's triangle: smooth across UV seams and
/// across the copies of a vertex a file splits, sharp across creases. Texel receivers interpolate
/// these, and stay close to their own triangle's plane: a normal tilted far from it would send
/// rays below the triangle, which the triangle itself then blocks. Zero-area triangles get
/// zero normals.
[[nodiscard]] std::vector<glm::vec3> corner_normals(std::span<const glm::vec3> corner_positions, float crease_degrees);

/// The crease angle texel receivers use: wider than the facets of a finely tessellated curve,
/// narrower than the corner of a box.
inline constexpr float kCreaseDegrees = 45.0f;

}  // namespace exao::bake
