// glTF 2.0 (.gltf/.glb) reader: the file through tinygltf, then the default scene's world-space
// triangles, one copy per node (and per EXT_mesh_gpu_instancing row) that uses a mesh, by the
// walk the bake shares (io/gltf_walk.h), which checks every index and accessor before any byte
// is read.

#include <tiny_gltf.h>

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "io/gltf_cutouts.h"
#include "io/gltf_file.h"
#include "io/gltf_model.h"
#include "io/gltf_walk.h"
#include "io/load_scene.h"

namespace exao {
namespace {

using namespace gltf;  // the shared reader: io/gltf_file.h, gltf_model.h, gltf_walk.h

// The scene is the walk's (io/gltf_walk.h, shared with the bake), with its cut-outs
// (io/gltf_cutouts.h); the rest of it is dropped.
Result<Scene> build_scene(const ModelBytes& source, std::span<const std::vector<std::uint8_t>> images) {
  Result<ModelWalk> walk = walk_model(source);
  if (!walk) return std::unexpected(walk.error());
  walk->scene.cutouts = read_cutouts(source, *walk, images, walk->scene.report.notes);
  return std::move(walk->scene);
}

// Images are kept encoded (keep_image_bytes); only cut-out materials' are decoded, and a missing
// one is not an error.
Result<Scene> load(const std::string& path) {
  std::vector<std::vector<std::uint8_t>> images;
  // Draco and meshopt decoded; a GLB's mesh bytes read in place (io/glb_in_place.h).
  Result<File> file = read_file(path, &keep_image_bytes, &images, BinChunk::InPlace);
  if (!file) return std::unexpected(file.error());
  images.resize(file->model.images.size());
  Result<Scene> scene = build_scene(file->bytes(), images);
  if (scene) scene->report.notes.insert(scene->report.notes.end(), file->notes.begin(), file->notes.end());
  return scene;
}

}  // namespace

Result<Scene> load_gltf(const std::string& path) {
  Result<Scene> scene = read_guarded<Scene>(path, [&] { return load(path); });
  if (scene) scene->name = std::filesystem::path(path).stem().string();
  return scene;
}

}  // namespace exao
