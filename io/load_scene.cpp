// Chooses a loader by file extension; open_scene takes a built-in scene's name first.

#include "io/load_scene.h"

#include "core/file_kind.h"

#include <cctype>
#include <filesystem>
#include <string>

namespace exao {

Result<Scene> load_scene(const std::string& path, const ProgressCallback& progress) {
  // A folder or a FIFO is said to be one (and a FIFO is never opened: it would block).
  if (const std::string problem = not_a_regular_file(path); !problem.empty()) return fail(path + ": " + problem);
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (ext == ".gltf" || ext == ".glb") return load_gltf(path);
  if (ext == ".obj" || ext == ".ply" || ext == ".off" || ext == ".stl") {
    return load_polygon_soup(path, progress);
  }
  const std::string what = ext.empty() ? "has no extension" : "has unknown extension '" + ext + "'";
  return fail(path + ": " + what + " (supported: .gltf, .glb, .obj, .ply, .off, .stl)");
}

Result<Scene> open_scene(const std::string& name_or_path, const ProgressCallback& progress) {
  for (const std::string& name : builtin_scene_names()) {
    if (name == name_or_path) return builtin_scene(name);
  }
  return load_scene(name_or_path, progress);
}

}  // namespace exao
