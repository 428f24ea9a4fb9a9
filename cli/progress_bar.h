#pragma once
// A progress bar on stderr when stderr is a terminal; silent otherwise (logs, CI, pipes).

#include <chrono>
#include <mutex>
#include <string>

#include "core/progress.h"

namespace exao::cli {

class ProgressBar {
 public:
  explicit ProgressBar(std::string label);
  ~ProgressBar();
  ProgressBar(const ProgressBar&) = delete;
  ProgressBar& operator=(const ProgressBar&) = delete;

  /// A callback for the library; thread-safe, redraws at most ten times a second.
  [[nodiscard]] ProgressCallback callback();
  /// Clears the bar's line.
  void finish();

 private:
  void draw(std::size_t done, std::size_t total);

  std::string label_;
  bool enabled_;
  bool drawn_ = false;
  std::mutex mutex_;
  std::chrono::steady_clock::time_point start_;
  std::chrono::steady_clock::time_point last_draw_;
};

}  // namespace exao::cli
