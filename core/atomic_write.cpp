#include "core/atomic_write.h"

#include <array>
#include <atomic>
#include <cstring>
#include <filesystem>
#include <mutex>

#include <unistd.h>

namespace exao {
namespace {

// Fixed slots of plain char arrays, because a signal handler may read them at any moment.
constexpr int kSlots = 16;
constexpr std::size_t kPathMax = 4096;
std::array<std::array<char, kPathMax>, kSlots> g_temp_paths{};
std::array<std::atomic<bool>, kSlots> g_in_use{};
std::mutex g_slot_mutex;

int claim_slot(const std::string& temp_path) {
  if (temp_path.size() >= kPathMax) return -1;
  std::lock_guard lock(g_slot_mutex);
  for (int i = 0; i < kSlots; ++i) {
    if (!g_in_use[i].load()) {
      std::memcpy(g_temp_paths[i].data(), temp_path.c_str(), temp_path.size() + 1);
      g_in_use[i].store(true);
      return i;
    }
  }
  return -1;
}

void release_slot(int slot) {
  if (slot >= 0) g_in_use[slot].store(false);
}

}  // namespace

Result<void> write_atomically(const std::string& path,
                              const std::function<Result<void>(const std::string& temp_path)>& write) {
  namespace fs = std::filesystem;
  const fs::path target(path);
  const fs::path folder = target.has_parent_path() ? target.parent_path() : fs::path(".");
  std::error_code ec;
  if (!fs::is_directory(folder, ec)) return fail(path + ": folder " + folder.string() + " does not exist");
  if (::access(folder.c_str(), W_OK) != 0) return fail(path + ": folder " + folder.string() + " is not writable");
  if (fs::is_directory(target, ec)) return fail(path + ": is a folder, not a file");

  std::string temp_name = ".";
  temp_name.append(target.filename().string()).append(".tmp-").append(std::to_string(::getpid()));
  const std::string temp_path = (folder / temp_name).string();
  const int slot = claim_slot(temp_path);
  Result<void> written = write(temp_path);
  if (written) {
    fs::rename(temp_path, target, ec);
    if (ec) written = fail(path + ": cannot rename the finished file into place: " + ec.message());
  }
  if (!written) fs::remove(temp_path, ec);
  release_slot(slot);
  return written;
}

void remove_unfinished_outputs() {
  for (int i = 0; i < kSlots; ++i) {
    if (g_in_use[i].load()) ::unlink(g_temp_paths[i].data());
  }
}

}  // namespace exao
