#pragma once
// ASCII PLY read straight into a Scene for the layout nearly every such file has: a "vertex"
// element of scalars with x, y, z (float or double), then a "face" element of one list of int or
// uint indices. CGAL 5.5's reader takes every value through its stream (about 50 MB/s); this
// one reads the same values with the same rounding (io/stream_cursor.h) and leaves every other
// file to CGAL.

#include <optional>
#include <string_view>

#include "core/error.h"
#include "core/progress.h"
#include "core/scene.h"

namespace exao {

/// The scene of an ASCII PLY whose bytes are `file`, which io/soup_prescan.h's ply_problem_in has
/// passed, exactly as the CGAL path makes it (every triangle two-sided, polygons fan-triangulated,
/// degenerate and non-finite triangles skipped and counted). nullopt, and the caller reads the
/// file with CGAL, for any other layout (other elements, "vertices"/"faces", list properties
/// among the vertex's, face properties besides the list, index items other than int or uint) and
/// wherever CGAL's stream might read a value otherwise or fail: a number it would not take or
/// would take as infinite, an integer with a sign or beyond its type (counts and indices are
/// plain digits), a face index past the vertices, data that ends early. `progress` gets (bytes
/// parsed, file size).
[[nodiscard]] std::optional<Result<Scene>> read_ascii_ply(std::string_view file, const ProgressCallback& progress = {});

}  // namespace exao
