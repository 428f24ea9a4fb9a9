#pragma once
// OBJ, PLY, OFF and STL scenes, through CGAL's polygon-soup reader. A header of its own so that
// code which reads only these formats (the kernel tests' real scenes) needs no glTF reader.

#include <string>

#include "core/error.h"
#include "core/progress.h"
#include "core/scene.h"

namespace exao {

/// Which reader a polygon soup goes through: the fast paths where they take the file (PLY, binary
/// STL, OBJ, OFF), else CGAL's; or CGAL's alone, the reference the fast paths are tested
/// against (they give its scene and its errors, bit for bit).
enum class SoupPath { Fast, Cgal };

/// Loads `.obj`/`.ply`/`.off`/`.stl`: every triangle two-sided (these formats carry no
/// sidedness), polygons fan-triangulated. Same contract as load_scene (io/load_scene.h):
/// degenerate or non-finite triangles are skipped and counted in `Scene::report`, and a missing,
/// unreadable or malformed file, or one with no triangle left, fails with one line naming it.
/// PLY (binary and ASCII), binary STL, OBJ and ASCII OFF are read straight into the scene where
/// their fast paths take the file (io/ply_binary_reader.h, io/ply_ascii_reader.h,
/// io/stl_binary_reader.h, io/obj_ascii_reader.h, io/off_ascii_reader.h), the rest by CGAL. `progress` gets (done,
/// total) work units: the file's bytes read, then made into triangles; or the bytes parsed; or
/// the bytes CGAL's reader has taken.
[[nodiscard]] Result<Scene> load_polygon_soup(const std::string& path, const ProgressCallback& progress = {},
                                              SoupPath reader = SoupPath::Fast);

}  // namespace exao
