#pragma once
// Helpers shared by the tests: where the real scenes are, and temporary folders.

#include <filesystem>
#include <string>

namespace exao::test {

/// `../shared/scenes/<relative>` when the scenes folder exists, else empty: tests that need
/// a real scene call GTEST_SKIP() on an empty path, so a user's clone reports them skipped.
[[nodiscard]] std::filesystem::path real_scene(const std::string& relative);

/// A fresh, empty folder under the system temporary folder, removed when the object dies.
class TempDir {
 public:
  TempDir();
  ~TempDir();
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  [[nodiscard]] const std::filesystem::path& path() const { return path_; }
  [[nodiscard]] std::filesystem::path operator/(const std::string& name) const { return path_ / name; }

 private:
  std::filesystem::path path_;
};

/// Writes `contents` to `path` (binary), replacing it.
void write_file(const std::filesystem::path& path, const std::string& contents);

struct CommandResult {
  int status;          // the exit status, or -1 when the command was killed by a signal (a crash)
  std::string output;  // stdout and stderr together
};

/// Runs a shell command, collecting what it prints.
[[nodiscard]] CommandResult run_command(const std::string& command);

/// Runs `prefix exec EXAO_BINARY arguments` (prefix may set limits, e.g. ulimit) through /bin/sh.
[[nodiscard]] CommandResult run_exao(const std::string& binary, const std::string& arguments,
                                     const std::string& prefix = "");

/// The bad-input contract: a plain non-zero exit (not a signal), one line, naming `names`.
void expect_one_line_error(const CommandResult& run, const std::string& names);

}  // namespace exao::test

#define EXAO_REQUIRE_SCENE(path)                                                     \
  do {                                                                               \
    if ((path).empty()) GTEST_SKIP() << "real scenes not found (set EXAO_SCENES_DIR)"; \
  } while (0)
