// `exao compare` end to end: every output appears, the table names every method, and bad options
// get one line naming the option and a non-zero exit.

#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <sys/wait.h>

#include <nlohmann/json.hpp>

#include "tests/test_support.h"

namespace exao {
namespace {

using test::CommandResult;
using test::expect_one_line_error;

CommandResult exao(const std::string& arguments) { return test::run_exao(EXAO_BINARY, arguments); }


TEST(CompareCli, WritesImagesHeatMapsSheetJsonAndTable) {
  test::TempDir dir;
  const std::string out = (dir / "cmp").string();
  const CommandResult run = exao("compare hidden-box -W 64 -H 48 -n 64 --stereo 0.05 --key world -o " + out);
  ASSERT_EQ(run.status, 0) << run.output;
  for (const char* name : {"exact", "hbao", "hbao-plus", "vao", "sdao", "svao", "rtsvao", "abuffer", "shbao-plus", "shbao-plus2d", "sdao-plus",
                           "mvsdao-plus", "rtsvao-rays", "abuffer-m4", "abuffer-m8", "abuffer-oit"}) {
    EXPECT_TRUE(std::filesystem::exists(dir / "cmp" / (std::string(name) + ".exr"))) << name;
    EXPECT_TRUE(std::filesystem::exists(dir / "cmp" / (std::string(name) + ".png"))) << name;
    if (std::string(name) != "exact") {
      EXPECT_TRUE(std::filesystem::exists(dir / "cmp" / (std::string(name) + "-error.png"))) << name;
    }
  }
  EXPECT_TRUE(std::filesystem::exists(dir / "cmp" / "contact-sheet.png"));
  std::ifstream json_file(dir / "cmp" / "compare.json");
  const nlohmann::json j = nlohmann::json::parse(json_file);
  ASSERT_EQ(j["methods"].size(), 15u);  // the default is every method
  for (const auto& m : j["methods"]) {
    EXPECT_GE(m["mean_abs"].get<double>(), 0.0);
    EXPECT_LE(m["within_255"].get<double>(), m["within_16"].get<double>());
    EXPECT_TRUE(m.contains("stereo"));
  }
  EXPECT_TRUE(j["exact"].contains("stereo"));
  EXPECT_TRUE(j.contains("secondary_camera"));
  for (const auto& m : j["methods"]) {
    const std::string name = m["name"];
    if (name == "abuffer-m4" || name == "abuffer-m8") {
      EXPECT_TRUE(m.contains("against")) << name;
    }
  }
  std::ifstream md_file(dir / "cmp" / "compare.md");
  std::stringstream md;
  md << md_file.rdbuf();
  for (const char* label : {"HBAO", "HBAO+", "VAO", "SD-HBAO", "SD-SVAO", "RT-SVAO", "A-BUFFER", "S-HBAO+", "S-HBAO+ 2D", "SD-HBAO+",
                            "MV-SD-HBAO+", "RT-SVAO RAYS", "A-BUFFER M=4", "A-BUFFER M=8", "A-BUFFER OIT", "stereo E"}) {
    EXPECT_NE(md.str().find(label), std::string::npos) << label;
  }
}

TEST(CompareCli, MethodsAllAndTheGrazingBox) {
  test::TempDir dir;
  const CommandResult run = exao("compare grazing-box -r 1 -W 48 -H 36 -n 32 --methods all -o " + (dir / "cmp").string());
  ASSERT_EQ(run.status, 0) << run.output;
  for (const char* label : {"| HBAO |", "| S-HBAO+ |", "| MV-SD-HBAO+ |", "| RT-SVAO RAYS |", "| A-BUFFER M=8 |", "| A-BUFFER OIT |"}) {
    EXPECT_NE(run.output.find(label), std::string::npos) << label;
  }
}

TEST(CompareCli, BadOptionsGetOneLine) {
  test::TempDir dir;
  const std::string out = " -W 32 -H 24 -n 32 -o " + (dir / "cmp").string();
  expect_one_line_error(exao("compare --methods hbao,foo" + out), "--methods");
  expect_one_line_error(exao("compare --methods hbao,hbao" + out), "twice");
  expect_one_line_error(exao("compare --sd-samples 0" + out), "--sd-samples");
  expect_one_line_error(exao("compare --sd-alpha 1.5" + out), "--sd-alpha");
  expect_one_line_error(exao("compare --thickness 3" + out), "--thickness");
  expect_one_line_error(exao("compare --directions 0" + out), "--directions");
  expect_one_line_error(exao("compare --blur -2" + out), "--blur");
  expect_one_line_error(exao("compare --key-cell 0" + out), "--key-cell");
  expect_one_line_error(exao("compare --stereo -1" + out), "--stereo");
  expect_one_line_error(exao("compare --key hash" + out), "--key");
  expect_one_line_error(exao("compare -r 0" + out), "--radius");
  expect_one_line_error(exao("compare no-such-scene.glb" + out), "no-such-scene.glb");
  expect_one_line_error(exao("compare --mv-angle 0" + out), "--mv-angle");
  expect_one_line_error(exao("compare --methods all,hbao" + out), "twice");
}

}  // namespace
}  // namespace exao
