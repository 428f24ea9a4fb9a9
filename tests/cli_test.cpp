// The exao program end to end: outputs appear whole, bad input gets one clear line and a
// non-zero exit, and inputs are never overwritten.

#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sys/wait.h>

#include "tests/test_support.h"

namespace exao {
namespace {

struct CommandResult {
  int status;
  std::string output;  // stdout and stderr together
};

CommandResult exao(const std::string& arguments) {
  const std::string command = std::string(EXAO_BINARY) + " " + arguments + " 2>&1";
  FILE* pipe = ::popen(command.c_str(), "r");
  std::string output;
  std::array<char, 4096> buffer{};
  while (pipe && std::fgets(buffer.data(), buffer.size(), pipe)) output += buffer.data();
  const int status = pipe ? ::pclose(pipe) : -1;
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, output};
}

// One line, naming what was wrong.
void expect_one_line_error(const CommandResult& run, const std::string& names) {
  EXPECT_NE(run.status, 0) << run.output;
  EXPECT_EQ(std::count(run.output.begin(), run.output.end(), '\n'), 1) << run.output;
  EXPECT_NE(run.output.find(names), std::string::npos) << run.output;
}

std::size_t files_in(const std::filesystem::path& dir) {
  return static_cast<std::size_t>(std::distance(std::filesystem::directory_iterator(dir), {}));
}

TEST(Cli, RenderWritesExrAndPngAndNothingElse) {
  test::TempDir dir;
  const CommandResult run = exao("render plane-pair -W 40 -H 30 -n 64 -o " + (dir / "a.exr").string() + " --png " + (dir / "a.png").string());
  ASSERT_EQ(run.status, 0) << run.output;
  EXPECT_GT(std::filesystem::file_size(dir / "a.exr"), 100u);
  EXPECT_GT(std::filesystem::file_size(dir / "a.png"), 50u);
  EXPECT_EQ(files_in(dir.path()), 2u) << "no temporary file left behind";
}

TEST(Cli, InfoDescribesTheDefaultScene) {
  const CommandResult run = exao("info");
  ASSERT_EQ(run.status, 0) << run.output;
  EXPECT_NE(run.output.find("triangles"), std::string::npos);
  EXPECT_NE(run.output.find("radius"), std::string::npos);
}

TEST(Cli, BadInputGetsOneClearLine) {
  test::TempDir dir;
  const std::string out = " -W 8 -H 8 -o " + (dir / "a.exr").string() + " --png " + (dir / "a.png").string();
  expect_one_line_error(exao("render " + (dir / "missing.glb").string() + out), "missing.glb");
  expect_one_line_error(exao("render plane-pair --samples 100" + out), "100");
  expect_one_line_error(exao("render plane-pair --radius 0" + out), "--radius");
  expect_one_line_error(exao("render plane-pair --radius -1" + out), "--radius");
  expect_one_line_error(exao("render plane-pair --radius 5%%x" + out), "--radius");
  expect_one_line_error(exao("render plane-pair --falloff cubic" + out), "cubic");
  expect_one_line_error(exao("render plane-pair --camera nowhere" + out), "nowhere");
  expect_one_line_error(exao("render plane-pair -W 8 -H 8 -o /nonexistent-folder/a.exr --png ''"), "/nonexistent-folder");
  test::write_file(dir / "empty.obj", "# nothing here\n");
  expect_one_line_error(exao("render " + (dir / "empty.obj").string() + out), "empty.obj");
  EXPECT_EQ(files_in(dir.path()), 1u) << "a failed run writes nothing";
}

TEST(Cli, NeverOverwritesTheInput) {
  test::TempDir dir;
  const std::string scene = (dir / "tri.obj").string();
  const std::string contents = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
  test::write_file(scene, contents);
  expect_one_line_error(exao("render " + scene + " -W 8 -H 8 -o " + scene + " --png ''"), "tri.obj");
  std::ifstream in(scene);
  const std::string after((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(after, contents);
}

}  // namespace
}  // namespace exao
