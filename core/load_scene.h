#pragma once
// Reading scenes from files, and the built-in procedural scenes.

#include <string>
#include <vector>

#include "core/error.h"
#include "core/scene.h"

namespace exao {

/// Loads `.gltf`/`.glb` (tinygltf) or `.obj`/`.ply`/`.off`/`.stl` (CGAL's polygon-soup
/// reader), chosen by extension (case-insensitive). glTF triangles are one-sided unless
/// their material is `doubleSided`; the other formats are two-sided. Triangles of zero area
/// or with non-finite vertices are skipped and counted in `Scene::report`. Fails with a one-line
/// error naming the file when it is missing, unreadable, malformed, or has no triangle left.
[[nodiscard]] Result<Scene> load_scene(const std::string& path);

/// Loaders by format, for callers who know it. Same contract as load_scene.
[[nodiscard]] Result<Scene> load_gltf(const std::string& path);
[[nodiscard]] Result<Scene> load_polygon_soup(const std::string& path);

/// Names of the built-in scenes; the first is the default.
[[nodiscard]] std::vector<std::string> builtin_scene_names();

/// A built-in scene by name ("room", "plane-pair", "sphere-on-plane", "corners"), or an error.
[[nodiscard]] Result<Scene> builtin_scene(const std::string& name);

/// `name` is a built-in scene's name, or else a path: the one entry point for every command.
[[nodiscard]] Result<Scene> open_scene(const std::string& name_or_path);

}  // namespace exao
