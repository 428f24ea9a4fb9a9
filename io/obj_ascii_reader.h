#pragma once
// Wavefront OBJ read straight into a Scene: one pass over the file's bytes, numbers parsed with
// std::from_chars. CGAL 5.5's reader (CGAL/IO/OBJ.h) takes each line through a std::istringstream
// and each number through the stream's num_get (under 40 MB/s, docs/scale.md); this reader
// follows its grammar exactly, so that every file it takes gives CGAL's scene bit for bit, and
// leaves every other file to CGAL.

#include <optional>
#include <string_view>

#include "core/error.h"
#include "core/progress.h"
#include "core/scene.h"

namespace exao {

/// The scene of the OBJ whose bytes are `file`, exactly as the CGAL path makes it (every triangle
/// two-sided, polygons fan-triangulated in file order, degenerate and non-finite triangles
/// skipped and counted, "N faces with fewer than 3 vertices skipped"). It reads `v` and `f` lines
/// as CGAL does (a vertex's first three numbers as libstdc++'s `>> double` takes them; a face's
/// integers each up to the next space, `v/vt/vn` forms included, negative indices relative to the
/// vertices so far) and skips the statements CGAL ignores. nullopt, and the caller reads the file
/// with CGAL, for everything else: a statement CGAL refuses, a number CGAL's stream would not
/// take (or takes otherwise: beyond double range), a face index that is not a vertex read so far
/// (CGAL resolves forward references, or fails), a file with no vertex or no face. So every error
/// CGAL's path reports is its own. `progress` gets (bytes parsed, file size).
[[nodiscard]] std::optional<Result<Scene>> read_ascii_obj(std::string_view file, const ProgressCallback& progress = {});

}  // namespace exao
