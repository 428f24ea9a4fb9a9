// Every subcommand x method x mask mode of the exao program either runs or refuses with one
// line that says why (engine/capabilities.h), decided when the options are checked: nothing
// crashes, nothing quietly computes another method. The table of what each method serves is
// written here again, independently of the engine's, so that a change to either shows.

#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <string>

#include "tests/test_support.h"

namespace exao {
namespace {

using test::CommandResult;

CommandResult exao(const std::string& arguments) { return test::run_command(std::string(EXAO_BINARY) + " " + arguments); }

constexpr std::array<const char*, 4> kMethods{"embree", "brute", "bvh", "raster"};
constexpr std::array<const char*, 2> kMasks{"lut", "exact"};
constexpr std::array<const char*, 4> kCommands{"render", "bake", "query", "bench"};

// raster draws a camera's G-buffer: it has receivers only at pixels.
bool serves(const std::string& command, const std::string& method) {
  return method != "raster" || command == "render" || command == "bench";
}

// A small run of `command` with `method` and `masks`, writing into `dir`.
std::string arguments(const std::string& command, const std::string& method, const std::string& masks,
                      const test::TempDir& dir) {
  const std::string out = (dir / "out").string();
  const std::string common = " plane-pair -n 32 --masks " + masks;
  if (command == "render") return "render" + common + " --method " + method + " -W 12 -H 9 -o " + out + ".exr --png ''";
  if (command == "bake") return "bake" + common + " --method " + method + " --preview '' -o " + out + ".glb";
  if (command == "query") {
    return "query" + common + " --method " + method + " --points " + (dir / "points.txt").string() + " -o " + out + ".txt";
  }
  return "bench" + common + " --methods " + method + " -W 12 -H 9 -r 5%";
}

TEST(CliMatrix, EveryCommandMethodAndMaskModeRunsOrSaysWhy) {
  test::TempDir dir;
  test::write_file(dir / "points.txt", "0 0.001 0 0 1 0\n0.3 0.001 0.2 0 1 0\n");
  for (const char* command : kCommands) {
    for (const char* method : kMethods) {
      for (const char* masks : kMasks) {
        SCOPED_TRACE(std::string(command) + " --method " + method + " --masks " + masks);
        const CommandResult run = exao(arguments(command, method, masks, dir));
        if (serves(command, method)) {
          EXPECT_EQ(run.status, 0) << run.output;
          EXPECT_EQ(run.output.find("exao:"), std::string::npos) << run.output;
          if (std::string(command) != "bench") {
            EXPECT_NE(run.output.find(method), std::string::npos) << run.output;
          }
        } else {
          EXPECT_EQ(run.status, 1) << run.output;
          EXPECT_EQ(std::count(run.output.begin(), run.output.end(), '\n'), 1) << run.output;
          EXPECT_EQ(run.output.rfind("exao: --method: raster", 0), 0u) << run.output;
          EXPECT_NE(run.output.find("pixels"), std::string::npos) << run.output;
        }
      }
    }
  }
}

// Regression: `exao bake --compare raster` crashed (segmentation fault, exit 139).
TEST(CliMatrix, BakeCompareRasterIsOneLineNotACrash) {
  test::TempDir dir;
  const CommandResult run = exao("bake plane-pair -n 32 --compare raster --preview '' -o " + (dir / "a.glb").string());
  EXPECT_EQ(run.status, 1) << run.output;
  EXPECT_EQ(std::count(run.output.begin(), run.output.end(), '\n'), 1) << run.output;
  EXPECT_EQ(run.output.rfind("exao: --compare: raster", 0), 0u) << run.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "a.glb")) << "refused before any work";
}

TEST(CliMatrix, BakeCompareRunsEveryMethodThatServesPoints) {
  test::TempDir dir;
  for (const char* method : {"embree", "brute", "bvh"}) {
    SCOPED_TRACE(method);
    const CommandResult run = exao("bake plane-pair -n 32 --compare " + std::string(method) + " --preview '' -o " +
                                   (dir / "a.glb").string());
    EXPECT_EQ(run.status, 0) << run.output;
    EXPECT_NE(run.output.find("identical"), std::string::npos) << run.output;
  }
  const CommandResult unknown = exao("bake plane-pair -n 32 --compare nonsense --preview '' -o " + (dir / "a.glb").string());
  EXPECT_EQ(unknown.status, 1) << unknown.output;
  EXPECT_EQ(unknown.output.rfind("exao: --compare: unknown method 'nonsense'", 0), 0u) << unknown.output;
}

// Library errors name options; the program prints its flags (cli/option_flags.cpp).
TEST(CliMatrix, ErrorsNameTheFlagAndTheValue) {
  test::TempDir dir;
  const std::string out = " -W 8 -H 8 -o " + (dir / "a.exr").string() + " --png ''";
  const std::string bake = " -n 32 --preview '' -o " + (dir / "a.glb").string();
  const struct {
    std::string arguments;
    std::string starts;
  } cases[] = {
      {"render plane-pair -n 100" + out, "exao: --samples: must be a multiple of 32 from 32 to 1024, got 100"},
      {"render plane-pair --table-resolution 2" + out, "exao: --table-resolution: must be from 4 to 256"},
      {"render plane-pair --branching 3" + out, "exao: --branching: must be 2 or 4, got 3"},
      {"render plane-pair --leaf-size 9" + out, "exao: --leaf-size: must be from 1 to 8, got 9"},
      {"render plane-pair --alpha 0" + out, "exao: --alpha: must be a finite number > 0"},
      {"render plane-pair --masks fuzzy" + out, "exao: --masks: unknown mask mode 'fuzzy'"},
      {"render plane-pair --method fast" + out, "exao: --method: unknown method 'fast'"},
      {"render plane-pair --embree-rays packet3" + out, "exao: --embree-rays: unknown mode 'packet3'"},
      {"render plane-pair --offset -1" + out, "exao: --offset: must be a finite length >= 0"},
      {"bench plane-pair -n 32,100 -W 8 -H 8", "exao: --samples: must be a multiple of 32 from 32 to 1024, got 100"},
      {"bench plane-pair --methods fast -W 8 -H 8", "exao: --methods: unknown method 'fast'"},
      {"bake plane-pair --png-bits 12" + bake, "exao: --png-bits: must be 8 or 16, got 12"},
      {"bake plane-pair --texture 8" + bake, "exao: --texture: the map size must be from 16 to 16384 texels, got 8"},
      {"bake plane-pair --texture 64 --texel-samples 3" + bake, "exao: --texel-samples: must be a square number"},
      {"bake plane-pair --texture 64 --uv-set 16" + bake, "exao: --uv-set: must be from 0 to 15, got 16"},
  };
  for (const auto& c : cases) {
    const CommandResult run = exao(c.arguments);
    EXPECT_EQ(run.status, 1) << c.arguments << "\n" << run.output;
    EXPECT_EQ(std::count(run.output.begin(), run.output.end(), '\n'), 1) << c.arguments << "\n" << run.output;
    EXPECT_EQ(run.output.rfind(c.starts, 0), 0u) << c.arguments << "\n" << run.output;
  }
}

}  // namespace
}  // namespace exao
