#pragma once
// The procedural scenes exao generates itself, so every command runs with no file and the tests
// have analytic answers. All are in metres-like units, +Y up, one-sided with fronts facing the
// open space.

#include <cstdint>
#include <string>
#include <vector>

#include "core/cutouts.h"
#include "core/error.h"
#include "core/scene.h"

namespace exao {

/// A closed 10 x 4 x 8 room (walls facing in) with two stacked boxes, a sphere on the floor and
/// a floor-to-ceiling column: corners, contact shadows and creases. Has a camera inside.
[[nodiscard]] Scene make_room();

/// Two parallel squares of half-size `half_size` centred on the Y axis: a floor at y = 0 facing
/// up and a ceiling at y = height facing down. With constant falloff, a point near the centre
/// of the floor has AO = (h / r)^2 for r > h (h measured from the ray origin).
[[nodiscard]] Scene make_plane_pair(float height = 0.5f, float half_size = 4.0f);

/// A unit sphere resting on an 8 x 8 floor.
[[nodiscard]] Scene make_sphere_on_plane();

/// Seed 000's Fig. 1-2 case: a 1 x 1 x 1 box on a 12 x 12 floor, its -X face at x = 0.1, hidden
/// from the camera ("view", at x = 0.3) by a thin wall 2 to 2.1 in front of it; the floor just
/// left of the box (x < 0.1) is seen, and the box is within reach of its AO (radius 1) while the
/// wall is not (over 1.4 away). The box's triangles come last, so removing it (box = false)
/// leaves every other triangle's index; wall = false removes the wall.
[[nodiscard]] Scene make_hidden_box(bool box = true, bool wall = true);
/// The cases of the surface rule (docs/surface-rule.md) on a 4 x 1.5 x 4 corner: a floor and two
/// walls meeting at the origin, a box on the floor and one against a wall (faces in the planes
/// of the floor and the wall), and two two-sided quads through each other, one tilted. Grid
/// vertices every 0.25, all exact in float, on every corner, edge and crossing line, so vertex
/// receivers (and offset 0) start exactly in the planes of their neighbours. Has a camera.
[[nodiscard]] Scene make_corners();

/// Cut-outs (core/cutouts.h): a 12 x 12 ground facing up and 7 x 7 two-sided cards, 1.2 wide and
/// 1.6 tall, standing 0.05 above it at fixed pseudo-random yaws and leans, their alpha an 8 x 8
/// checker (32 x 32 texels, linear filtering, alphaMode MASK at 0.5): half of every card is open.
/// cut_out = false: the same triangles, every one opaque. Has a camera ("field").
[[nodiscard]] Scene make_foliage(bool cut_out = true);

/// Appends the quad a, b, b + d - a, d (counter-clockwise seen from its front) as two triangles
/// of `material` (an index in cutouts.materials), UV (0, 1), (1, 1), (1, 0), (0, 0) at its
/// corners, recorded in `cutouts` (whose of_triangle grows with the scene). For scenes made in
/// code (tests, make_foliage).
void add_cutout_quad(Scene& scene, Cutouts& cutouts, const glm::vec3& a, const glm::vec3& b, const glm::vec3& d,
                     std::uint32_t material, bool two_sided);

/// Names of the built-in scenes; the first is the default.
[[nodiscard]] std::vector<std::string> builtin_scene_names();

/// A built-in scene by name ("room", "plane-pair", "sphere-on-plane", "hidden-box", "corners",
/// "foliage"),
/// or an error.
[[nodiscard]] Result<Scene> builtin_scene(const std::string& name);

}  // namespace exao
