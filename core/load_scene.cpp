// Chooses a loader by file extension. The built-in scenes and open_scene live in
// builtin_scenes.cpp.

#include "core/load_scene.h"

#include <cctype>
#include <filesystem>
#include <string>

namespace exao {

Result<Scene> load_scene(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) return fail(path + ": no such file");
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (ext == ".gltf" || ext == ".glb") return load_gltf(path);
  if (ext == ".obj" || ext == ".ply" || ext == ".off" || ext == ".stl") {
    return load_polygon_soup(path);
  }
  const std::string what = ext.empty() ? "has no extension" : "has unknown extension '" + ext + "'";
  return fail(path + ": " + what + " (supported: .gltf, .glb, .obj, .ply, .off, .stl)");
}

}  // namespace exao
