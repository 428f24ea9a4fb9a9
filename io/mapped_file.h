#pragma once
// exao::MappedFile: a file's bytes, read-only, mapped into memory rather than copied into a
// buffer. A loader that reads the bytes once gets them from the page cache without a copy and
// without faulting in fresh pages of its own: perf put 40% of a big GLB's load in page faults
// (docs/scale.md, "Loading"). Internal to io/.

#include <cstddef>
#include <string>
#include <string_view>

namespace exao {

class MappedFile {
 public:
  /// Maps the regular file at `path` whole, for reading front to back. An empty file maps to no
  /// bytes.
  /// ok() is false when the file cannot be opened or mapped (a folder, a FIFO, no such file).
  explicit MappedFile(const std::string& path);
  ~MappedFile();
  MappedFile(const MappedFile&) = delete;
  MappedFile& operator=(const MappedFile&) = delete;

  [[nodiscard]] bool ok() const { return ok_; }
  /// The file's bytes, valid while this object lives; a file truncated meanwhile by another
  /// process makes reading past its new end fault (SIGBUS), as with any mapping.
  [[nodiscard]] std::string_view bytes() const { return {static_cast<const char*>(data_), size_}; }

 private:
  void* data_ = nullptr;
  std::size_t size_ = 0;
  bool ok_ = false;
};

}  // namespace exao
