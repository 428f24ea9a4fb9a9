#pragma once
// Long library jobs report progress through a callback the caller gives; the library never prints.

#include <atomic>
#include <cstddef>
#include <functional>

namespace exao {

/// Called with (done, total) work units, from any worker thread, possibly concurrently.
using ProgressCallback = std::function<void(std::size_t done, std::size_t total)>;

/// Counts finished work across threads and forwards it to the callback.
class ProgressCounter {
 public:
  ProgressCounter(const ProgressCallback& callback, std::size_t total) : callback_(callback), total_(total) {}
  void add(std::size_t finished) {
    const std::size_t done = done_.fetch_add(finished) + finished;
    if (callback_) callback_(done, total_);
  }

 private:
  const ProgressCallback& callback_;
  std::size_t total_;
  std::atomic<std::size_t> done_{0};
};

}  // namespace exao
