#pragma once
// OBJ, PLY, OFF and STL scenes, through CGAL's polygon-soup reader. A header of its own so that
// code which reads only these formats (the kernel tests' real scenes) needs no glTF reader.

#include <string>

#include "core/error.h"
#include "core/progress.h"
#include "core/scene.h"

namespace exao {

/// Loads `.obj`/`.ply`/`.off`/`.stl`: every triangle two-sided (these formats carry no
/// sidedness), polygons fan-triangulated. Same contract as load_scene (io/load_scene.h):
/// degenerate or non-finite triangles are skipped and counted in `Scene::report`, and a missing,
/// unreadable or malformed file, or one with no triangle left, fails with one line naming it.
/// Binary PLY and STL are read straight into the scene (io/ply_binary_reader.h,
/// io/stl_binary_reader.h), the rest by CGAL. `progress` gets (done, total) work units: the
/// file's bytes read, then made into triangles; or the bytes CGAL's reader has taken.
[[nodiscard]] Result<Scene> load_polygon_soup(const std::string& path, const ProgressCallback& progress = {});

}  // namespace exao
