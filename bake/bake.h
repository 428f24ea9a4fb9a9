#pragma once
// exao::bake::bake: AO baked into a glTF model, per vertex or per texel. The AO comes from the
// library engine (engine/engine.h, any method that serves points), so the bake only decides where
// the receivers are and where their values go.

#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "bake/document.h"
#include "core/error.h"
#include "engine/engine.h"
#include "core/progress.h"
#include "core/receiver_frame.h"

namespace exao::bake {

enum class Target { Vertex, Texture };
enum class VertexChannel { Color, Attribute };  // COLOR_0 (multiplied into an existing one), or _AO
enum class NormalSource { Geometric, File };     // area-weighted face normals, or the file's NORMAL
/// Where a texture bake's UVs come from: the file's set (File), a chart atlas made for the bake
/// (Generate: box projection, no overlaps, even texel density, padded; written as a new
/// TEXCOORD_n that the occlusionTexture reads), or per primitive the file's set when it can hold
/// AO and a generated one when it covers no area, overlaps itself on more than 1% of its area,
/// leaves [0, 1] or is missing (Auto, the default). Every decision is reported in the notes.
enum class UvMode { Auto, File, Generate };

struct BakeOptions {
  Target target = Target::Vertex;
  VertexChannel channel = VertexChannel::Color;
  NormalSource normals = NormalSource::Geometric;
  int texture_size = 1024;     // texels per side of each AO map, 16 to 16384
  int uv_set = 0;              // TEXCOORD_<uv_set> lays the maps out (seen through the KHR_texture_transform of
                               // the slot AO shares: occlusionTexture, else metallicRoughnessTexture, else another)
  UvMode uv = UvMode::Auto;
  int texel_samples = 4;       // receivers per texel: a square number (1 = the texel centre)
  int margin = 4;              // dilation rings around each chart, texels (0 to 64)
};

/// Checks the options of a texture bake (vertex bakes have none to check); the error names the
/// field ("texel_samples: ...") and its value.
[[nodiscard]] Result<void> check_options(const BakeOptions& options);

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

/// Bakes: finds the receivers, asks `engine` about them (progress in receivers), and writes the
/// result into the document's
/// model (vertex: a COLOR_0 or _AO accessor per primitive, meshes split per node where their AO
/// differs; texture: maps, and each material's occlusionTexture with texCoord = the set laid out
/// by and the KHR_texture_transform it was seen through, its other textures kept; primitives on
/// generated UVs get their vertices split along chart seams and the new set). `engine` must be
/// built from document.scene() for Receivers::Points. Fails, naming the problem, on bad options
/// (naming the field: "texel_samples: ..."), or with UvMode::File a primitive without the UV set
/// (the message suggests a vertex bake) or UVs outside [0, 1].
[[nodiscard]] Result<BakeResult> bake(Document& document, const BakeOptions& options, const engine::Engine& engine,
                                      const ProgressCallback& progress = {});
/// bake() with the engine's per-call settings: exao merge supplies every receiver's count from
/// the parts of a sharded bake (engine::RunOptions::supplied_blocked), so that the atlas, the
/// dilation and the files are made once, from the complete answers, exactly as one run makes them.
[[nodiscard]] Result<BakeResult> bake(Document& document, const BakeOptions& options, const engine::Engine& engine,
                                      const engine::RunOptions& run);

/// The receivers bake() would ask the engine about, in its order, without computing AO or
/// changing the document (exao bench --receivers times methods on them). Fails as bake() does.
[[nodiscard]] Result<std::vector<Receiver>> bake_receivers(Document& document, const BakeOptions& options);

}  // namespace exao::bake
