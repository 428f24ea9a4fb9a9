#include "tests/test_support.h"

#include <atomic>
#include <fstream>
#include <random>

#include <unistd.h>

namespace exao::test {

std::filesystem::path real_scene(const std::string& relative) {
  const std::filesystem::path path = std::filesystem::path(EXAO_SCENES_DIR) / relative;
  return std::filesystem::exists(path) ? path : std::filesystem::path();
}

TempDir::TempDir() {
  static std::atomic<int> counter{0};
  path_ = std::filesystem::temp_directory_path() /
          ("exao-test-" + std::to_string(::getpid()) + "-" + std::to_string(counter++));
  std::filesystem::remove_all(path_);
  std::filesystem::create_directories(path_);
}

TempDir::~TempDir() {
  std::error_code ignored;
  std::filesystem::remove_all(path_, ignored);
}

void write_file(const std::filesystem::path& path, const std::string& contents) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << contents;
}

}  // namespace exao::test
