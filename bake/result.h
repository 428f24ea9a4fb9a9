#pragma once
// What a bake found and computed: its receivers and their AO, the AO maps of a texture bake and
// where each part's values went, and the notes for the user. Filled by the bake's steps
// (bake/texture_steps.h, bake/bake.cpp), read by the writers (bake/save.h, bake/preview.h).

#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "bake/options.h"
#include "core/receiver_frame.h"

namespace exao::bake {

/// One AO map: every primitive (of the default scene) with the same material shares it.
struct AoMap {
  int material = -1;                 // glTF material it belongs to (-1: primitives without one)
  std::string label;                 // for file names: "" when it is the only map, else "m<index>"
  int size = 0;                      // width = height
  std::vector<float> ao;             // size * size, row-major from the top row (v = 0)
  std::vector<std::uint8_t> filled;  // 1 covered by a triangle, 2 filled by the margin, 0 background
  std::size_t covered_texels = 0;
  std::size_t overlap_texels = 0;
  int image = -1;                    // the glTF image that will hold it
};

struct BakeResult {
  Target target = Target::Vertex;
  std::vector<Receiver> receivers;   // everything the engine was asked about
  std::vector<float> ao;             // its answers
  double ao_seconds = 0.0;           // time spent in the engine
  std::vector<AoMap> maps;           // texture bakes
  /// Texture bakes: per receiver, its map and texel (y * size + x).
  std::vector<std::uint32_t> receiver_map, receiver_texel;
  /// Per part (a primitive as drawn by one node): vertex bakes hold the AO per vertex (1 where
  /// no triangle uses the vertex); texture bakes the UV per vertex and the part's map.
  std::vector<std::vector<float>> part_vertex_ao;
  std::vector<std::vector<glm::vec2>> part_uv;         // empty for parts on generated UVs
  /// Texture bakes: per part, the map UV of each triangle corner, three per triangle, in the
  /// front-face order of ModelWalk::corners (file and generated UVs alike).
  std::vector<std::vector<glm::vec2>> part_corner_uv;
  std::vector<int> part_map;
  std::size_t meshes_split = 0;      // vertex bakes: new meshes made for nodes whose AO differs
  std::vector<std::string> notes;    // one line each, for the user
};

}  // namespace exao::bake
