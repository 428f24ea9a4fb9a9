#pragma once
// The exao program as a function: main() calls it with argv, and embedding callers (the Python
// module's exao.bake and exao.render, python/) call it in-process with the same arguments, so
// the program's options, defaults and messages exist once.

#include <functional>
#include <string>
#include <vector>

#include "core/progress.h"

namespace exao::cli {

/// Where an embedding caller wants what the program would show on a terminal. Process-wide:
/// set it around one run_program call at a time (the caller serialises runs).
struct Embedding {
  /// Receives each error line report() prints ("--samples: must be ..."); the line is then not
  /// printed to stderr, so the caller shows it once (as an exception).
  std::function<void(const std::string& message)> error;
  /// Receives every progress bar's (done, total), from worker threads; it may throw to cancel
  /// the job (the exception leaves run_program, which removes unfinished outputs first).
  ProgressCallback progress;
};

/// The embedding in force, or nullptr (the plain program).
[[nodiscard]] const Embedding* embedding();

/// Runs `exao <args...>` (args excludes the program name): parses the subcommand and its flags
/// and runs it. Returns the exit status (0 success, 1 bad input). A command-line parse error
/// ("The following argument was not expected: --foo") goes to embedding->error when one is given,
/// else CLI11 prints it (and --help) as the program always has.
[[nodiscard]] int run_program(const std::vector<std::string>& args, const Embedding* embedding = nullptr);

}  // namespace exao::cli
