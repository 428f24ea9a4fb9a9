#pragma once
// Binary PLY read straight into a Scene: one pass over the file's bytes, no per-value stream
// parsing. CGAL's reader takes about 50 ns a value through its streams; this reads the common
// layouts (float or double x, y, z; a face list of int or uint indices; any other scalar
// properties skipped by size) at memory speed, and leaves every other file to CGAL.

#include <optional>
#include <string_view>

#include "core/error.h"
#include "core/progress.h"
#include "core/scene.h"

namespace exao {

/// The scene of a binary PLY whose bytes are `file`, which io/soup_prescan.h's ply_problem_in
/// has passed: every triangle two-sided, polygons fan-triangulated, degenerate and non-finite
/// triangles skipped and counted, a face index past the vertices an error naming the face (as
/// the CGAL path says it). nullopt when the layout is not one this reader takes (ASCII, a list
/// among the vertex properties, float list counts, no vertex or face element...): the caller
/// then reads the file with CGAL. Every read is bounds-checked, so a file that passed no
/// pre-scan is refused rather than read past its end. `progress` gets (bytes read, file size).
[[nodiscard]] std::optional<Result<Scene>> read_binary_ply(std::string_view file, const ProgressCallback& progress = {});

}  // namespace exao
