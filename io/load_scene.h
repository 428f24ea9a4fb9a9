#pragma once
// Reading scenes from files, and the one entry point that takes a built-in scene's name or a path.

#include <string>

#include "core/builtin_scenes.h"
#include "core/error.h"
#include "core/progress.h"
#include "core/scene.h"
#include "io/polygon_soup_loader.h"

namespace exao {

/// Loads `.gltf`/`.glb` (tinygltf) or `.obj`/`.ply`/`.off`/`.stl` (CGAL's polygon-soup
/// reader), chosen by extension (case-insensitive). glTF triangles are one-sided unless
/// their material is `doubleSided`; the other formats are two-sided. Triangles of zero area
/// or with non-finite vertices are skipped and counted in `Scene::report`. Fails with a one-line
/// error naming the file when it is missing, unreadable, malformed, or has no triangle left.
/// `progress` gets (done, total) work units for the polygon soups (io/polygon_soup_loader.h);
/// glTF reports nothing.
[[nodiscard]] Result<Scene> load_scene(const std::string& path, const ProgressCallback& progress = {});

/// The glTF loader, for callers who know the format. Same contract as load_scene
/// (io/polygon_soup_loader.h has the other formats' loader).
[[nodiscard]] Result<Scene> load_gltf(const std::string& path);

/// `name` is a built-in scene's name, or else a path: the one entry point for every command.
[[nodiscard]] Result<Scene> open_scene(const std::string& name_or_path, const ProgressCallback& progress = {});

}  // namespace exao
