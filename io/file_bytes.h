#pragma once
// exao::read_file_bytes: a whole file into memory, the one way io/'s readers read a file they
// parse from memory (the binary PLY and STL readers, the pre-scan of CGAL's inputs, glTF and GLB
// files before tinygltf sees them).

#include <string>
#include <vector>

#include "core/progress.h"

namespace exao {

/// Replaces `out` with every byte of the file at `path`, in large reads (16 MiB; a byte-at-a-time
/// stream iterator is far slower on large files); `progress` gets (bytes read, size) after each.
/// False when the file does not open, its size cannot be had, or it reads short; `out` then
/// holds what was read, or nothing.
[[nodiscard]] bool read_file_bytes(const std::string& path, std::string& out, const ProgressCallback& progress = {});
[[nodiscard]] bool read_file_bytes(const std::string& path, std::vector<unsigned char>& out,
                                   const ProgressCallback& progress = {});

}  // namespace exao
