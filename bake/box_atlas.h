#pragma once
// A texture atlas for meshes that come without usable UVs (built-in scenes, OBJ and friends, and
// glTF primitives whose UVs cannot hold AO: `exao bake --uv generate|auto`): box projection.
// Each triangle goes to the axis its normal is closest to; charts grow from a seed triangle
// across shared edges (vertices welded by position) to neighbours of the same axis whose
// projection onto that axis's plane does not overlap the chart's (a separating-axis test), so
// no chart folds onto itself even where a surface winds round; charts are packed on shelves into
// [0, 1]^2 at one common scale, so texel density is the same everywhere, with `padding` texels
// between charts and around the border.

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
