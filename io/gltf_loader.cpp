// glTF 2.0 (.gltf/.glb) reader: the file through tinygltf, then the default scene's world-space
// triangles, one copy per node (and per EXT_mesh_gpu_instancing row) that uses a mesh, by the
// walk the bake shares (io/gltf_walk.h), which checks every index and accessor before any byte
// is read.

#include <tiny_gltf.h>

#include <filesystem>
#include <string>
#include <utility>

#include "io/gltf_file.h"
#include "io/gltf_model.h"
#include "io/gltf_walk.h"
#include "io/load_scene.h"

namespace exao {
namespace {

using namespace gltf;  // the shared reader: io/gltf_file.h, gltf_model.h, gltf_walk.h

// The scene is the walk's (io/gltf_walk.h, shared with the bake); the rest of it is dropped.
Result<Scene> build_scene(const tinygltf::Model& model) {
  Result<ModelWalk> walk = walk_model(model);
  if (!walk) return std::unexpected(walk.error());
  return std::move(walk->scene);
}

// AO needs no texture: images are neither decoded nor required to exist.
bool ignore_image(tinygltf::Image*, const int, std::string*, std::string*, int, int,
                  const unsigned char*, int, void*) {
  return true;
}

Result<Scene> load(const std::string& path) {
  Result<File> file = read_file(path, &ignore_image, nullptr);  // Draco and meshopt decoded
  if (!file) return std::unexpected(file.error());
  Result<Scene> scene = build_scene(file->model);
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
