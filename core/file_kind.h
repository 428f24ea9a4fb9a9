#pragma once
// What a path names, in words, for errors about inputs and outputs that are not plain files.

#include <string>

namespace exao {

/// "" when `path` is a regular file (after following symbolic links); otherwise what it is:
/// "no such file", "is a folder, not a file", "is a FIFO, not a regular file", "is a device,
/// not a regular file", "is a socket, not a regular file". Never blocks (a FIFO is not opened).
[[nodiscard]] std::string not_a_regular_file(const std::string& path);

}  // namespace exao
