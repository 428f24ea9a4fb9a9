// `exao bake` end to end: the default run, files written beside the output, the Khronos glTF
// validator on bakes of the built-in room and the Khronos samples, bad input, and an
// interrupted run that leaves nothing behind.

#include <gtest/gtest.h>

#include <array>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <thread>

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include "tests/test_support.h"

extern char** environ;

namespace exao {
namespace {

namespace fs = std::filesystem;

using test::CommandResult;

CommandResult run(const std::string& command) { return test::run_command(command); }

CommandResult exao(const std::string& arguments) { return run(std::string(EXAO_BINARY) + " " + arguments); }

using test::expect_one_line_error;

std::set<std::string> files_in(const fs::path& dir) {
  std::set<std::string> out;
  for (const auto& entry : fs::directory_iterator(dir)) out.insert(entry.path().filename().string());
  return out;
}

// Built with += : GCC 12 warns (-Wrestrict, a false positive) on "'" + string + "'".
std::string quote(const fs::path& p) {
  std::string out = "'";
  out += p.string();
  out += "'";
  return out;
}

// One triangle (facing +Z) and a floor under it, as a .gltf with an embedded buffer; `uv` adds
// TEXCOORD_0 (scaled by uv_scale).
void write_triangles(const fs::path& path, bool uv, float uv_scale = 1.0f) {
  const float data[] = {0, 0, 1, 1, 0, 1, 0, 1, 1, -2, -2, 0, 2, -2, 0, 0, 2, 0};
  std::vector<float> uvs;
  for (int v = 0; v < 6; ++v) uvs.insert(uvs.end(), {uv_scale * (0.1f + 0.1f * static_cast<float>(v)), uv_scale * (0.8f - 0.1f * static_cast<float>(v))});
  std::string bytes(reinterpret_cast<const char*>(data), sizeof data);
  bytes.append(reinterpret_cast<const char*>(uvs.data()), uvs.size() * sizeof(float));
  static constexpr char kDigits[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string b64;
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    std::uint32_t v = static_cast<std::uint8_t>(bytes[i]) << 16;
    if (i + 1 < bytes.size()) v |= static_cast<std::uint8_t>(bytes[i + 1]) << 8;
    if (i + 2 < bytes.size()) v |= static_cast<std::uint8_t>(bytes[i + 2]);
    b64 += kDigits[v >> 18 & 63];
    b64 += kDigits[v >> 12 & 63];
    b64 += i + 1 < bytes.size() ? kDigits[v >> 6 & 63] : '=';
    b64 += i + 2 < bytes.size() ? kDigits[v & 63] : '=';
  }
  test::write_file(path, std::string(R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
    "meshes": [{"primitives": [{"attributes": {"POSITION": 0)") + (uv ? R"(, "TEXCOORD_0": 1)" : "") + R"(}}]}],
    "buffers": [{"uri": "data:application/octet-stream;base64,)" + b64 + R"(", "byteLength": 120}],
    "bufferViews": [{"buffer": 0, "byteLength": 72}, {"buffer": 0, "byteOffset": 72, "byteLength": 48}],
    "accessors": [{"bufferView": 0, "componentType": 5126, "count": 6, "type": "VEC3", "min": [-2, -2, 0], "max": [2, 2, 1]},
                  {"bufferView": 1, "componentType": 5126, "count": 6, "type": "VEC2"}]})");
}

TEST(BakeCli, DefaultBakeWritesTheRoomAndAPreview) {
  test::TempDir dir;
  const CommandResult result = run("cd " + quote(dir.path()) + " && " + EXAO_BINARY + " bake -n 32");
  ASSERT_EQ(result.status, 0) << result.output;
  EXPECT_EQ(files_in(dir.path()), (std::set<std::string>{"room.glb", "room-preview.png"}));
  EXPECT_NE(result.output.find("vertex receivers"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("Mrays/s"), std::string::npos) << result.output;
}

TEST(BakeCli, TextureBakeWritesMapsBesideTheGltf) {
  test::TempDir dir;
  const CommandResult result =
      exao("bake room --texture 128 -n 32 --png-bits 16 --compare embree -o " + quote(dir / "r.gltf"));
  ASSERT_EQ(result.status, 0) << result.output;
  EXPECT_EQ(files_in(dir.path()),
            (std::set<std::string>{"r.gltf", "r.bin", "r_ao.png", "r_ao.exr", "r-preview.png"}));
  std::ifstream in(dir / "r.gltf");
  const std::string json((std::istreambuf_iterator<char>(in)), {});
  EXPECT_NE(json.find("\"occlusionTexture\""), std::string::npos);
  EXPECT_NE(json.find("\"r_ao.png\""), std::string::npos);
  EXPECT_NE(json.find("\"r.bin\""), std::string::npos);
  // --compare times the reference on the same receivers, from the same run.
  EXPECT_NE(result.output.find("embree"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("identical"), std::string::npos) << result.output;
  // A 16-bit greyscale PNG: bit depth 16, colour type 0 in the header.
  std::ifstream png(dir / "r_ao.png", std::ios::binary);
  std::array<unsigned char, 26> header{};
  png.read(reinterpret_cast<char*>(header.data()), header.size());
  EXPECT_EQ(header[24], 16);
  EXPECT_EQ(header[25], 0);
}

// --compare with exact masks prints the agreement ray by ray, and sorts the rays that differ
// into grazing or not (docs/surface-rule.md): on `corners`, vertex receivers on every corner
// and edge, none may differ but by grazing.
TEST(BakeCli, CompareWithExactMasksReportsGrazingRays) {
  test::TempDir dir;
  const CommandResult result =
      exao("bake corners -n 64 --masks exact --compare embree --preview '' -o " + quote(dir / "c.glb"));
  ASSERT_EQ(result.status, 0) << result.output;
  EXPECT_NE(result.output.find("rays agree"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("grazing"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find(", 0 by a ray that does not graze"), std::string::npos) << result.output;
}

TEST(BakeCli, ObjInputIsConvertedToGlb) {
  test::TempDir dir;
  test::write_file(dir / "tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 3 4\nf 1 4 2\n");
  const CommandResult result = run("cd " + quote(dir.path()) + " && " + EXAO_BINARY + " bake tri.obj -n 32 --preview ''");
  ASSERT_EQ(result.status, 0) << result.output;
  EXPECT_EQ(files_in(dir.path()), (std::set<std::string>{"tri.obj", "tri.glb"}));
}

// The Khronos validator, from scripts/install-test-tools.sh; missing: the test says so and skips.
class Validator : public ::testing::Test {
 protected:
  void SetUp() override {
    if (run("node --version").status != 0) GTEST_SKIP() << "node is not installed: the glTF validator cannot run";
    if (!fs::exists(fs::path(EXAO_TEST_TOOLS) / "node_modules" / "gltf-validator")) {
      GTEST_SKIP() << "the glTF validator is not installed: run scripts/install-test-tools.sh " << EXAO_BUILD_DIR;
    }
  }

  // Image files the input names but the shared scenes leave out (SOURCES.md): the output still
  // names them, and the validator's IO_ERROR for them is the input's, not the bake's.
  static std::string missing_images(const fs::path& input) {
    if (input.extension() != ".gltf") return "";
    std::ifstream in(input);
    const std::string json((std::istreambuf_iterator<char>(in)), {});
    const std::regex uri("\"uri\"\\s*:\\s*\"([^\"]+)\"");
    std::string out;
    for (auto it = std::sregex_iterator(json.begin(), json.end(), uri); it != std::sregex_iterator(); ++it) {
      const std::string name = (*it)[1];
      if (name.rfind("data:", 0) != 0 && !fs::exists(input.parent_path() / name)) out += (out.empty() ? "" : ",") + name;
    }
    return out;
  }

  static CommandResult validate(const fs::path& file, const std::string& missing_ok) {
    return run("node " + quote(EXAO_VALIDATE_SCRIPT) + " --modules " + quote(EXAO_TEST_TOOLS) +
               (missing_ok.empty() ? "" : " --missing-ok '" + missing_ok + "'") + " " + quote(file));
  }
};

TEST_F(Validator, PassesOnEveryBake) {
  struct Case {
    std::string scene;    // built-in name or path under the shared scenes
    std::string options;
    std::string output;
  };
  const std::vector<Case> cases = {
      {"room", "", "room.glb"},
      {"room", "--texture 128", "room-texture.glb"},
      {"room", "--attribute", "room-attribute.gltf"},
      {"plane-pair", "--texture 64", "plane-pair.gltf"},
      {"CesiumMilkTruck/glTF/CesiumMilkTruck.gltf", "", "truck.gltf"},
      {"CesiumMilkTruck/glTF/CesiumMilkTruck.gltf", "--texture 128", "truck-texture.glb"},
      {"CesiumMilkTruck/glTF/CesiumMilkTruck.gltf", "--texture 128 --normals file", "truck-texture.gltf"},
      {"Duck/glTF/Duck.gltf", "--attribute", "duck.glb"},
      {"Duck/glTF-Binary/Duck.glb", "--texture 128", "duck-texture.gltf"},
      {"Duck/glTF-Quantized/Duck.gltf", "--normals file", "duck-quantized.gltf"},
      {"BoxInterleaved/glTF/BoxInterleaved.gltf", "", "box-interleaved.gltf"},
      {"Box/glTF-Embedded/Box.gltf", "", "box-embedded.gltf"},
      {"SimpleSparseAccessor/glTF/SimpleSparseAccessor.gltf", "", "sparse.gltf"},
      {"SimpleInstancing/glTF/SimpleInstancing.gltf", "", "instancing.glb"},
      {"NegativeScaleTest/glTF/NegativeScaleTest.gltf", "", "negative-scale.gltf"},
      {"MeshPrimitiveModes/glTF/MeshPrimitiveModes.gltf", "", "modes.gltf"},
      {"MultipleScenes/glTF/MultipleScenes.gltf", "", "multiple-scenes.gltf"},
      {"OrientationTest/glTF-Binary/OrientationTest.glb", "", "orientation.glb"},
      {"Fox/glTF/Fox.gltf", "--texture 128", "fox.gltf"},
      {"AlphaBlendModeTest/glTF/AlphaBlendModeTest.gltf", "--texture 64", "alpha.glb"},
      // Generated AO UV sets (issue 15): quantised attributes, skins and instancing copied along
      // the split vertices, and the ground plane.
      {"Duck/glTF-Quantized/Duck.gltf", "--texture 128", "duck-quantized-texture.gltf"},
      {"Fox/glTF/Fox.gltf", "--texture 128 --uv generate", "fox-generated.glb"},
      {"SimpleInstancing/glTF/SimpleInstancing.gltf", "--texture 64 --uv generate", "instancing-generated.gltf"},
      {"Box/glTF-Binary/Box.glb", "--texture 64 --ground", "box-ground.glb"},
  };
  test::TempDir dir;
  std::size_t validated = 0;
  for (const Case& c : cases) {
    fs::path input = c.scene;
    std::string missing;
    if (c.scene.find('/') != std::string::npos) {
      input = test::real_scene(c.scene);
      if (input.empty()) continue;
      missing = missing_images(input);
    }
    const fs::path output = dir / c.output;
    const CommandResult baked = exao("bake " + quote(input) + " " + c.options + " -n 32 --preview '' -o " + quote(output));
    ASSERT_EQ(baked.status, 0) << c.scene << " " << c.options << ":\n" << baked.output;
    const CommandResult checked = validate(output, missing);
    EXPECT_EQ(checked.status, 0) << c.scene << " " << c.options << " -> " << c.output << ":\n" << checked.output;
    EXPECT_NE(checked.output.find(": 0 errors"), std::string::npos) << checked.output;
    std::printf("%-55s %-32s %s", (c.scene + " " + c.options).c_str(), c.output.c_str(),
                checked.output.substr(checked.output.rfind(": ") + 2).c_str());
    ++validated;
  }
  EXPECT_GE(validated, 4u);
}

// The validator itself fails a broken file, so a pass means something.
TEST_F(Validator, RejectsABrokenFile) {
  test::TempDir dir;
  test::write_file(dir / "broken.gltf", R"({"asset": {"version": "2.0"}, "meshes": [{"primitives": [{"attributes": {"POSITION": 7}}]}]})");
  const CommandResult checked = validate(dir / "broken.gltf", "");
  EXPECT_EQ(checked.status, 1) << checked.output;
}

TEST(BakeCli, BadInputGetsOneClearLine) {
  test::TempDir dir;
  write_triangles(dir / "plain.gltf", false);
  write_triangles(dir / "tiling.gltf", true, 2.0f);
  write_triangles(dir / "fine.gltf", true);
  const std::string n = " -n 32 --preview '' ";
  expect_one_line_error(exao("bake " + quote(dir / "plain.gltf") + n + "--texture 64 --uv file -o " + quote(dir / "a.glb")),
                        "has no TEXCOORD_0: a texture bake needs UVs; bake per vertex");
  expect_one_line_error(exao("bake " + quote(dir / "tiling.gltf") + n + "--texture 64 --uv file -o " + quote(dir / "a.glb")),
                        "outside [0, 1]");
  expect_one_line_error(exao("bake " + quote(dir / "fine.gltf") + n + "--texture 64 --uv sometimes -o " + quote(dir / "a.glb")),
                        "--uv: must be auto, file or generate");
  expect_one_line_error(exao("bake " + quote(dir / "fine.gltf") + n + "-o " + quote(dir / "fine.gltf")),
                        "refusing to overwrite");
  expect_one_line_error(exao("bake " + quote(dir / "fine.gltf") + n + "-o " + quote(dir / "nowhere" / "a.glb")),
                        (dir / "nowhere").string());
  expect_one_line_error(exao("bake " + quote(dir / "fine.gltf") + n + "-o " + quote(dir / "a.obj")), "a.obj");
  expect_one_line_error(exao("bake " + quote(dir / "fine.gltf") + n + "--texture 64 --texel-samples 3 -o " + quote(dir / "a.glb")),
                        "--texel-samples");
  expect_one_line_error(exao("bake " + quote(dir / "fine.gltf") + n + "--texture 64 --vertex -o " + quote(dir / "a.glb")),
                        "--vertex and --texture");
  expect_one_line_error(exao("bake " + quote(dir / "missing.gltf") + n + "-o " + quote(dir / "a.glb")), "missing.gltf");
  // A folder nobody may write to: for root (who may write anywhere else) /proc.
  const fs::path locked = ::geteuid() == 0 ? fs::path("/proc") : dir / "locked";
  if (::geteuid() != 0) {
    fs::create_directory(locked);
    fs::permissions(locked, fs::perms::owner_read | fs::perms::owner_exec);
  }
  expect_one_line_error(exao("bake " + quote(dir / "fine.gltf") + n + "-o " + quote(locked / "a.glb")), locked.string());
  if (::geteuid() != 0) fs::permissions(locked, fs::perms::owner_all);
  EXPECT_EQ(files_in(dir.path()), (std::set<std::string>{"plain.gltf", "tiling.gltf", "fine.gltf"}) )
      << "a failed run writes nothing";
}

// SIGINT in the middle of a long bake: the program exits with 128 + 2 and leaves neither an
// output nor a temporary file.
TEST(BakeCli, AnInterruptedRunLeavesNothingBehind) {
  test::TempDir dir;
  const std::string output = (dir / "room.glb").string();
  std::vector<std::string> args = {EXAO_BINARY, "bake", "room", "--texture", "2048", "-n", "256", "-o", output};
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  pid_t child = 0;
  ASSERT_EQ(::posix_spawn(&child, EXAO_BINARY, nullptr, nullptr, argv.data(), environ), 0);
  std::this_thread::sleep_for(std::chrono::milliseconds(2500));
  ASSERT_EQ(::kill(child, SIGINT), 0);
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFEXITED(status)) << "the handler exits; a default SIGINT death would leave this false";
  EXPECT_EQ(WEXITSTATUS(status), 128 + SIGINT) << "still running after 2.5 s, as it should be";
  EXPECT_TRUE(files_in(dir.path()).empty()) << *files_in(dir.path()).begin();
}

}  // namespace
}  // namespace exao
