#pragma once
// Outputs are written to a temporary file beside the target and renamed into place, so a
// reader never sees a partial file and a failed run leaves the old file untouched.
//
// What may be replaced: a regular file, or nothing. An existing output that is a folder, a
// device, a FIFO or a socket is refused (renaming over `/dev/full` as root would replace the
// device node). A symbolic link is written through: the file it points to is replaced (the
// temporary file sits beside that file) and the link stays; a link to anything but a regular
// file (or to nothing) is refused.
//
// Temporary files are named `.NAME.exao-partial-PID`. A run that is killed outright (kill -9,
// a power cut) cannot remove its own, so every write first removes those of NAME whose PID is
// no longer a running process.

#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <string_view>

#include "core/error.h"

namespace exao {

/// Calls `write(temp_path)`, then renames temp_path into place. On any failure the temporary
/// file is removed and the error returned; a missing or unwritable folder, or an output that
/// is not a regular file, is reported by name before `write` is called.
[[nodiscard]] Result<void> write_atomically(
    const std::string& path, const std::function<Result<void>(const std::string& temp_path)>& write);

/// Writes `contents` as the whole of the file at `path`, through write_atomically. A failed
/// write is reported as "PATH: write failed: REASON", REASON the system's (system_reason).
[[nodiscard]] Result<void> write_file_atomically(const std::string& path, std::string_view contents);
[[nodiscard]] inline Result<void> write_file_atomically(const std::string& path, std::span<const std::uint8_t> contents) {
  return write_file_atomically(path, std::string_view(reinterpret_cast<const char*>(contents.data()), contents.size()));
}

/// Removes every temporary file that write_atomically has not finished with; for a signal
/// handler, so that an interrupted run leaves nothing behind. Async-signal-safe.
void remove_unfinished_outputs();

/// The system's reason for the last failed call, "File too large" or "No space left on
/// device", for errors that must say why a write failed: strerror(errno), or `fallback` when
/// errno is 0.
[[nodiscard]] std::string system_reason(const char* fallback = "unknown error");

}  // namespace exao
