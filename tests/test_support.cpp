#include "tests/test_support.h"

#include <gtest/gtest.h>

#include <algorithm>

#include <array>
#include <atomic>
#include <cstdio>
#include <fstream>
#include <random>

#include <sys/wait.h>
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

CommandResult run_exao(const std::string& binary, const std::string& arguments, const std::string& prefix) {
  return run_command(prefix + "exec " + binary + " " + arguments);
}

void expect_one_line_error(const CommandResult& run, const std::string& names) {
  EXPECT_GT(run.status, 0) << run.output;
  EXPECT_EQ(std::count(run.output.begin(), run.output.end(), '\n'), 1) << run.output;
  EXPECT_NE(run.output.find(names), std::string::npos) << "expected '" << names << "' in: " << run.output;
}

CommandResult run_command(const std::string& command) {
  FILE* pipe = ::popen((command + " 2>&1").c_str(), "r");
  std::string output;
  std::array<char, 4096> buffer{};
  while (pipe && std::fgets(buffer.data(), buffer.size(), pipe)) output += buffer.data();
  const int status = pipe ? ::pclose(pipe) : -1;
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, output};
}

}  // namespace exao::test
