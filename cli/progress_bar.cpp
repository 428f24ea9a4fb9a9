#include "cli/progress_bar.h"

#include <cstdio>

#include <unistd.h>

#include "cli/program.h"

namespace exao::cli {

ProgressBar::ProgressBar(std::string label)
    : label_(std::move(label)), enabled_(::isatty(STDERR_FILENO) == 1), start_(std::chrono::steady_clock::now()) {}

ProgressBar::~ProgressBar() { finish(); }

ProgressCallback ProgressBar::callback() {
  // An embedding caller draws its own progress (and may cancel from it); no bar on stderr then.
  if (const Embedding* e = embedding(); e && e->progress) return e->progress;
  if (!enabled_) return {};
  return [this](std::size_t done, std::size_t total) {
    std::unique_lock lock(mutex_, std::try_to_lock);
    if (!lock) return;  // another thread is drawing: skipping one update is fine
    draw(done, total);
  };
}

void ProgressBar::draw(std::size_t done, std::size_t total) {
  const auto now = std::chrono::steady_clock::now();
  if (drawn_ && done < total && now - last_draw_ < std::chrono::milliseconds(100)) return;
  // Nothing for jobs under a second: a flash of a bar is noise.
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  if (elapsed < 1.0 && !drawn_) return;
  last_draw_ = now;
  drawn_ = true;
  const double fraction = total ? static_cast<double>(done) / static_cast<double>(total) : 1.0;
  constexpr int kWidth = 30;
  const int filled = static_cast<int>(fraction * kWidth);
  char bar[kWidth + 1];
  for (int i = 0; i < kWidth; ++i) bar[i] = i < filled ? '#' : '.';
  bar[kWidth] = '\0';
  const double eta = fraction > 0.0 ? elapsed * (1.0 - fraction) / fraction : 0.0;
  std::fprintf(stderr, "\r%s [%s] %3d%%  %.0fs left   ", label_.c_str(), bar, static_cast<int>(100.0 * fraction), eta);
  std::fflush(stderr);
}

void ProgressBar::finish() {
  std::lock_guard lock(mutex_);
  if (enabled_ && drawn_) {
    std::fprintf(stderr, "\r%*s\r", static_cast<int>(label_.size()) + 50, "");
    std::fflush(stderr);
  }
  drawn_ = false;
}

}  // namespace exao::cli
