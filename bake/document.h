#pragma once
// exao::bake::Document: a glTF model being baked, with the scene its AO is computed against.
// A .gltf/.glb is read whole (nodes, materials, textures, extensions it does not know), so that
// everything survives the bake; a built-in scene or a polygon soup (OBJ, PLY, OFF, STL) is
// converted to a glTF model first, and then baked the same way.

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/scene.h"

namespace exao::bake {

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

class Document {
 public:
  struct Impl;  // tinygltf's model and the walk of its default scene; internal to exao_bake

  /// `name_or_path`: a built-in scene's name, a .gltf/.glb file (told by its extension,
  /// case-insensitive), or another format io/load_scene.h reads (converted with `convert`).
  /// Fails with one line naming the file and the problem.
  [[nodiscard]] static Result<Document> open(const std::string& name_or_path, const ConvertOptions& convert = {});

  /// A triangle soup as a glTF model: triangles grouped by (material, sidedness) into the
  /// primitives of one mesh, vertices welded where positions are equal, one glTF material per
  /// group (doubleSided as the triangles were), the scene's cameras as camera nodes.
  [[nodiscard]] static Result<Document> from_scene(const Scene& scene, const ConvertOptions& convert = {});

  Document(Document&&) noexcept;
  Document& operator=(Document&&) noexcept;
  ~Document();

  /// The scene the AO is computed against (world-space triangles of the default glTF scene).
  /// Mutable only so the caller can apply --sided before baking.
  [[nodiscard]] const Scene& scene() const;
  [[nodiscard]] Scene& scene();
  /// The scene's name: a built-in's name or the file's stem.
  [[nodiscard]] const std::string& name() const;
  /// True when read from a glTF file, false when converted.
  [[nodiscard]] bool from_gltf() const;
  /// Every file the input consists of (the glTF, its buffers and images): a bake never writes one.
  [[nodiscard]] const std::vector<std::string>& input_files() const;
  /// What the reader or the conversion left out or changed, one line each, for the user.
  [[nodiscard]] const std::vector<std::string>& notes() const;

  [[nodiscard]] Impl& impl() { return *impl_; }
  [[nodiscard]] const Impl& impl() const { return *impl_; }

 private:
  explicit Document(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace exao::bake
