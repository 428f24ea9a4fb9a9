#include "core/atomic_write.h"

#include <array>
#include <atomic>
#include <cerrno>
#include <charconv>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <mutex>

#include <signal.h>
#include <unistd.h>

#include "core/file_kind.h"

namespace exao {
namespace {

namespace fs = std::filesystem;

// Fixed slots of plain char arrays, because a signal handler may read them at any moment.
constexpr int kSlots = 16;
constexpr std::size_t kPathMax = 4096;
std::array<std::array<char, kPathMax>, kSlots> g_temp_paths{};
std::array<std::atomic<bool>, kSlots> g_in_use{};
std::mutex g_slot_mutex;

constexpr std::string_view kPartial = ".exao-partial-";

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

// Removes `.NAME.exao-partial-PID` files in `folder` left by runs that no longer exist. A PID
// that is alive (even if reused by another program) keeps its file: it may be writing it.
void remove_stale_partials(const fs::path& folder, const std::string& name) {
  const std::string prefix = "." + name + std::string(kPartial);
  std::error_code ec;
  for (fs::directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string file = it->path().filename().string();
    if (!file.starts_with(prefix)) continue;
    const std::string_view digits = std::string_view(file).substr(prefix.size());
    long pid = 0;
    const auto [end_of_number, error] = std::from_chars(digits.data(), digits.data() + digits.size(), pid);
    if (error != std::errc() || end_of_number != digits.data() + digits.size() || pid <= 0) continue;
    if (pid == static_cast<long>(::getpid())) continue;
    if (::kill(static_cast<pid_t>(pid), 0) == 0 || errno != ESRCH) continue;
    std::error_code ignored;
    if (it->is_regular_file(ignored)) fs::remove(it->path(), ignored);
  }
}

}  // namespace

std::string system_reason(const char* fallback) {
  const int error = errno;
  return error != 0 ? std::strerror(error) : fallback;
}

Result<void> write_atomically(const std::string& path,
                              const std::function<Result<void>(const std::string& temp_path)>& write) {
  std::error_code ec;
  fs::path target(path);
  // An existing output must be a regular file; a symbolic link is followed to one.
  if (fs::exists(fs::symlink_status(target, ec))) {
    if (const std::string problem = not_a_regular_file(path); !problem.empty()) {
      return fail(path + ": " + problem + "; refusing to replace it");
    }
    if (fs::is_symlink(fs::symlink_status(target, ec))) {
      const fs::path resolved = fs::canonical(target, ec);
      if (ec) return fail(path + ": cannot follow the symbolic link: " + ec.message());
      target = resolved;
    }
  }
  const fs::path folder = target.has_parent_path() ? target.parent_path() : fs::path(".");
  if (!fs::is_directory(folder, ec)) return fail(path + ": folder " + folder.string() + " does not exist");
  if (::access(folder.c_str(), W_OK) != 0) return fail(path + ": folder " + folder.string() + " is not writable");

  const std::string name = target.filename().string();
  remove_stale_partials(folder, name);
  std::string temp_name = ".";
  temp_name.append(name).append(kPartial).append(std::to_string(::getpid()));
  const std::string temp_path = (folder / temp_name).string();
  // A leftover of this very PID (a previous process that had it) is ours to replace.
  fs::remove(temp_path, ec);
  const int slot = claim_slot(temp_path);
  errno = 0;
  Result<void> written = write(temp_path);
  if (written) {
    fs::rename(temp_path, target, ec);
    if (ec) written = fail(path + ": cannot rename the finished file into place: " + ec.message());
  }
  if (!written) fs::remove(temp_path, ec);
  release_slot(slot);
  return written;
}

Result<void> write_file_atomically(const std::string& path, std::string_view contents) {
  return write_atomically(path, [&](const std::string& temp) -> Result<void> {
    std::ofstream out(temp, std::ios::binary | std::ios::trunc);
    out.write(contents.data(), static_cast<std::streamsize>(contents.size()));
    // close(), not flush(): the last buffered bytes may only fail to reach the disk here.
    out.close();
    if (!out) return fail(path + ": write failed: " + system_reason());
    return {};
  });
}

void remove_unfinished_outputs() {
  for (int i = 0; i < kSlots; ++i) {
    if (g_in_use[i].load()) ::unlink(g_temp_paths[i].data());
  }
}

}  // namespace exao
