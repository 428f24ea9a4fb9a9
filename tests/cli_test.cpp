// The exao program end to end: outputs appear whole, bad input gets one clear line and a
// non-zero exit, and inputs are never overwritten.

#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "tests/test_support.h"

namespace exao {
namespace {

using test::CommandResult;

CommandResult exao(const std::string& arguments) { return test::run_command(std::string(EXAO_BINARY) + " " + arguments); }

using test::expect_one_line_error;

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

std::vector<double> read_values(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::vector<double> values;
  double v = 0.0;
  while (in >> v) values.push_back(v);
  return values;
}

TEST(Cli, QueryGivesOneValuePerPointInOrderFromTextAndPly) {
  test::TempDir dir;
  // Points on the room's floor, near a wall and in the open, with explicit keys 0..k-1 so that
  // the PLY (whose keys are vertex indices) asks for exactly the same rays.
  const float xs[] = {-4.9f, -2.0f, 0.0f, 1.6f, 4.5f};
  std::string text = "# x y z nx ny nz key\n";
  std::string ply = "ply\nformat ascii 1.0\nelement vertex 5\nproperty float x\nproperty float y\nproperty float z\n"
                    "property float nx\nproperty float ny\nproperty float nz\nend_header\n";
  for (int i = 0; i < 5; ++i) {
    const std::string p = std::to_string(xs[i]) + " 0 1.0 0 1 0";
    text += p + " " + std::to_string(i) + "\n";
    ply += p + "\n";
  }
  test::write_file(dir / "points.txt", text);
  test::write_file(dir / "points.ply", ply);
  const std::string common = " -n 256 --masks exact -o ";
  ASSERT_EQ(exao("query --points " + (dir / "points.txt").string() + common + (dir / "bvh.txt").string()).status, 0);
  ASSERT_EQ(exao("query --points " + (dir / "points.ply").string() + common + (dir / "ply.txt").string()).status, 0);
  ASSERT_EQ(exao("query --method embree --points " + (dir / "points.txt").string() + common + (dir / "embree.txt").string()).status, 0);
  const auto bvh = read_values(dir / "bvh.txt");
  ASSERT_EQ(bvh.size(), 5u);
  EXPECT_EQ(read_values(dir / "ply.txt"), bvh);
  const auto embree = read_values(dir / "embree.txt");
  ASSERT_EQ(embree.size(), 5u);
  for (int i = 0; i < 5; ++i) EXPECT_NEAR(bvh[i], embree[i], 2.0 / 256) << "point " << i;
  EXPECT_LT(bvh[0], bvh[2]) << "the point by the wall is darker than the one in the open";
  expect_one_line_error(exao("query --points " + (dir / "missing.txt").string() + " -o " + (dir / "x.txt").string()), "missing.txt");
  test::write_file(dir / "bad.txt", "1 2 3 0 1\n");
  expect_one_line_error(exao("query --points " + (dir / "bad.txt").string() + " -o " + (dir / "x.txt").string()), "line 1");
}

}  // namespace
}  // namespace exao
