#pragma once
// Outputs are written to a temporary file beside the target and renamed into place, so a
// reader never sees a partial file and a failed run leaves the old file untouched.

#include <functional>
#include <string>

#include "core/error.h"

namespace exao {

/// Calls `write(temp_path)`, then renames temp_path to `path`. On any failure the temporary
/// file is removed and the error returned; a missing or unwritable folder is reported by name.
[[nodiscard]] Result<void> write_atomically(
    const std::string& path, const std::function<Result<void>(const std::string& temp_path)>& write);

/// Removes every temporary file that write_atomically has not finished with; for a signal
/// handler, so that an interrupted run leaves nothing behind. Async-signal-safe.
void remove_unfinished_outputs();

}  // namespace exao
