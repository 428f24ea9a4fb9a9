#pragma once
// The bake's options: what bake() writes (BakeOptions) and how a triangle soup becomes the glTF
// model it bakes (ConvertOptions). A header of their own, below everything else of bake/, so
// that the steps and the writers include them without including the bake or the document.

#include <optional>

#include "core/error.h"

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

/// How a triangle soup becomes a glTF model.
struct ConvertOptions {
  /// 0: positions and indices only (enough for vertex bakes). Otherwise the side, in texels, of
  /// the AO texture the box-projection atlas (TEXCOORD_0) is laid out for.
  int atlas_size = 0;
  /// Texels kept free around every atlas chart, so that the map's dilation margin of one chart
  /// never reaches another; >= 2 * margin + 2 keeps bilinear filtering clean too.
  int atlas_padding = 10;
  /// exao bake --ground (applies to every input, glTF too): an occluding plane added to scene()
  /// only, never to the model, so it gets no receivers and is never written out
  /// (core/ground_plane.h). At `ground_height` along +Y, else at the model's lowest point.
  bool ground = false;
  std::optional<float> ground_height;
};

}  // namespace exao::bake
