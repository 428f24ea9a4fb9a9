#pragma once
// A texture atlas for meshes that come without UVs (built-in scenes, OBJ and friends): box
// projection. Each triangle goes to the axis its normal is closest to; edge-connected triangles
// of one axis form a chart, projected flat onto that axis's plane (the projection is one-to-one
// inside a chart because every normal there leans less than 55 degrees from the axis); charts
// are packed on shelves into [0, 1]^2 at one common scale, so texel density is the same
// everywhere, with `padding` texels between charts and around the border.

#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "core/error.h"

namespace exao::bake {

struct AtlasMesh {
  std::vector<std::uint32_t> source_vertex;  // per atlas vertex: the input vertex it copies
  std::vector<glm::vec2> uv;                 // per atlas vertex, in [0, 1]^2, v down (glTF)
  std::vector<std::uint32_t> triangles;      // three atlas vertices per input triangle, same order
  std::size_t charts = 0;
  float texels_per_unit = 0.0f;              // at `size`: the atlas's texel density
};

/// Atlas of the triangles (three indices into `positions` each; vertices shared by index) for a
/// size x size texture. A vertex is split once per chart it is in. Fails when the charts' padding
/// alone does not fit (too many charts for the size): the message says so.
[[nodiscard]] Result<AtlasMesh> box_atlas(std::span<const glm::vec3> positions, std::span<const std::uint32_t> triangles,
                                          int size, int padding);

}  // namespace exao::bake
