#pragma once
// ASCII OFF read straight into a Scene for the plain "OFF" header (no colours, normals, textures
// or homogeneous coordinates). CGAL 5.5's File_scanner_OFF takes every line through a
// std::istringstream (about 15 MB/s); this reader follows its reading line for line, with the
// same rounding (io/stream_cursor.h), and leaves every other file to CGAL and its pre-scan
// (io/soup_prescan.h's off_problem).

#include <optional>
#include <string_view>

#include "core/error.h"
#include "core/progress.h"
#include "core/scene.h"

namespace exao {

/// The scene of the OFF file whose bytes are `file`, exactly as the CGAL path makes it (every
/// triangle two-sided, polygons fan-triangulated, degenerate and non-finite triangles skipped and
/// counted). It reads as CGAL does: after the counts, '#' comments and white space skipped before
/// each vertex or face line, the line cut at a '#', a vertex's first three numbers, a face's size
/// and indices as the doubles CGAL reads and truncates. nullopt, and the caller pre-scans the file
/// and reads it with CGAL, for anything else: another header, comments before the counts, counts
/// CGAL would refuse or that the file cannot hold (the pre-scan's error), a number CGAL's stream
/// would not take, a size that is not a whole number, a size or index that is negative, not below
/// 2^53 or past the vertices, a vertex line that ends the file. `progress` gets (bytes parsed, file size).
[[nodiscard]] std::optional<Result<Scene>> read_ascii_off(std::string_view file, const ProgressCallback& progress = {});

}  // namespace exao
