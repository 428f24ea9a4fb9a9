#pragma once
// Binary STL read straight into a Scene: one pass over the file's 50-byte records. CGAL's reader
// takes each float through a stream and merges equal vertices in a std::map (about 1 us a
// triangle); the scene is a soup, so the merge changes nothing but where CGAL would make it
// change a float (see read_binary_stl), and those files are left to CGAL.

#include <optional>
#include <string_view>

#include "core/error.h"
#include "core/progress.h"
#include "core/scene.h"

namespace exao {

/// The scene of a binary STL whose bytes are `file`, exactly as the CGAL path makes it: every
/// triangle two-sided, in file order, corners in file order, degenerate and non-finite triangles
/// skipped and counted. nullopt when CGAL would read the file otherwise or change a float, and
/// the caller then reads it with CGAL: a file that CGAL takes for ASCII (it starts with "solid"
/// and holds "facet" or "endsolid"), one shorter than its stated count of facets (CGAL then
/// tries ASCII), one with no facet, and one with a NaN or a -0 coordinate (CGAL's vertex map
/// holds them equal to other vertices and substitutes those). `progress` gets (bytes read,
/// file size).
[[nodiscard]] std::optional<Result<Scene>> read_binary_stl(std::string_view file, const ProgressCallback& progress = {});

}  // namespace exao
