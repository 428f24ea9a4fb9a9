#pragma once
// Reading receivers for `exao query`: a text file with one receiver a line, or a PLY point cloud
// with normals.

#include <string>
#include <vector>

#include "core/error.h"
#include "core/receiver_frame.h"

namespace exao {

/// Text: one receiver a line, `x y z nx ny nz [key]`; blank lines and lines starting with '#'
/// are skipped; the key defaults to the (1-based) line number. PLY (by extension, ASCII or
/// binary, via CGAL): vertices with x y z nx ny nz; the key is the vertex index. Fails with one
/// line naming the file (and line) on a missing file, a malformed line, a non-finite value or a
/// zero normal, or a PLY without normals.
[[nodiscard]] Result<std::vector<Receiver>> load_receivers(const std::string& path);

/// Writes one value a line, in order, atomically.
[[nodiscard]] Result<void> save_values(const std::vector<float>& values, const std::string& path);

}  // namespace exao
