// Hostile input (issue 16): every class of crash, hang and replaced device that fuzzing found,
// each on an input the test writes itself. A regression here is a crash, a hang (CTest's
// timeout) or a message that no longer names the problem.

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <sys/wait.h>
#include <unistd.h>

#include "core/atomic_write.h"
#include "io/gltf_guard.h"
#include "io/load_scene.h"
#include "io/receiver_io.h"
#include "tests/test_support.h"

namespace exao {
namespace {

using test::CommandResult;
using test::expect_one_line_error;

CommandResult exao(const std::string& arguments, const std::string& prefix = "") {
  return test::run_exao(EXAO_BINARY, arguments, prefix);
}


namespace fs = std::filesystem;

void expect_error(const Result<Scene>& scene, const std::string& names) {
  ASSERT_FALSE(scene.has_value()) << "loaded " << scene->triangle_count() << " triangles";
  EXPECT_NE(scene.error().message.find(names), std::string::npos) << scene.error().message;
  EXPECT_EQ(scene.error().message.find('\n'), std::string::npos) << scene.error().message;
}

std::string read_file(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// A glTF with one triangle (positions (0,0,0), (1,0,0), (0,1,0) in a data URI, or in `uri`).
// `top` and `node` are extra members for the top level and for the node.
std::string triangle_gltf(const std::string& top = "", const std::string& node = "", const std::string& uri = "",
                          const std::string& camera_node = "") {
  const std::string data = uri.empty() ? "data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA"
                                       : uri;
  std::string nodes = "{\"mesh\": 0" + node + "}";
  std::string scene_nodes = "[0]";
  std::string cameras;
  if (!camera_node.empty()) {
    nodes += ", {\"camera\": 0, " + camera_node + "}";
    scene_nodes = "[0, 1]";
    cameras = ", \"cameras\": [{\"type\": \"perspective\", \"perspective\": {\"yfov\": 0.8, \"znear\": 0.1}}]";
  }
  return "{\"asset\": {\"version\": \"2.0\"}" + top + ", \"scene\": 0, \"scenes\": [{\"nodes\": " + scene_nodes +
         "}], \"nodes\": [" + nodes + "], \"meshes\": [{\"primitives\": [{\"attributes\": {\"POSITION\": 0}}]}]," +
         " \"accessors\": [{\"bufferView\": 0, \"componentType\": 5126, \"count\": 3, \"type\": \"VEC3\"," +
         " \"min\": [0, 0, 0], \"max\": [1, 1, 0]}], \"bufferViews\": [{\"buffer\": 0, \"byteLength\": 36}]," +
         " \"buffers\": [{\"byteLength\": 36, \"uri\": \"" + data + "\"}]" + cameras + "}";
}

std::string nested_arrays(std::size_t depth) { return std::string(depth, '[') + std::string(depth, ']'); }

// A GLB container around `json` (padded to 4 bytes) with no BIN chunk.
std::string glb(std::string json) {
  while (json.size() % 4 != 0) json += ' ';
  const auto u32 = [](std::uint32_t v) {
    return std::string{static_cast<char>(v & 0xFF), static_cast<char>(v >> 8 & 0xFF), static_cast<char>(v >> 16 & 0xFF),
                       static_cast<char>(v >> 24 & 0xFF)};
  };
  return "glTF" + u32(2) + u32(static_cast<std::uint32_t>(20 + json.size())) + u32(static_cast<std::uint32_t>(json.size())) +
         "JSON" + json;
}

const std::string kPlyVertexHeader =
    "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n";

// --- 1. Deep JSON nesting -----------------------------------------------------------------------

TEST(HostileInput, JsonDepthCountsOnlyBracketsOutsideStrings) {
  EXPECT_EQ(gltf::json_depth(R"({"a": [[1], {"b": "[[[[\"[["}]})"), 3u);
  EXPECT_EQ(gltf::json_depth("[]"), 1u);
  EXPECT_EQ(gltf::json_depth("\"\\\\\" [ ]"), 1u) << "an escaped backslash ends before the quote";
  EXPECT_GT(gltf::json_depth(nested_arrays(100000)), gltf::kMaxJsonDepth) << "stops counting past the limit";
}

TEST(HostileInput, DeepJsonNestingIsRefusedBeforeTinygltf) {
  test::TempDir dir;
  const std::string deep = nested_arrays(15000);  // overflowed the stack inside tinygltf
  const std::string limit = std::to_string(gltf::kMaxJsonDepth);
  test::write_file(dir / "top.gltf", triangle_gltf(", \"extras\": " + deep));
  test::write_file(dir / "node.gltf", triangle_gltf("", ", \"extras\": {\"a\": " + deep + "}"));
  test::write_file(dir / "deep.glb", glb(triangle_gltf(", \"extras\": " + deep)));
  expect_error(load_scene((dir / "top.gltf").string()), "nests deeper than " + limit);
  expect_error(load_scene((dir / "node.gltf").string()), "nests deeper than " + limit);
  expect_error(load_scene((dir / "deep.glb").string()), "nests deeper than " + limit);
  // The bake reads glTF with its own tinygltf context.
  expect_one_line_error(exao("bake " + (dir / "top.gltf").string() + " -o " + (dir / "out.glb").string()),
                        "nests deeper than " + limit);

  // Real nesting, well inside the limit, still loads.
  test::write_file(dir / "fine.gltf", triangle_gltf(", \"extras\": " + nested_arrays(gltf::kMaxJsonDepth - 10)));
  const Result<Scene> fine = load_scene((dir / "fine.gltf").string());
  ASSERT_TRUE(fine.has_value()) << fine.error().message;
  EXPECT_EQ(fine->triangle_count(), 1u);
}

// --- 2. PLY counts ------------------------------------------------------------------------------

TEST(HostileInput, PlyElementWithoutPropertiesAndAHugeCountIsRefused) {
  test::TempDir dir;
  // The 200-byte file that reached 4 GB in 22 s.
  test::write_file(dir / "a.ply", kPlyVertexHeader + "element vertex 2147483648\nend_header\n0 0 0\n1 0 0\n0 1 0\n");
  expect_error(load_scene((dir / "a.ply").string()), "2147483648 entries but no properties");
  test::write_file(dir / "b.ply", kPlyVertexHeader + "element face 99999999999\nproperty list uchar int vertex_indices\n"
                                                     "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
  expect_error(load_scene((dir / "b.ply").string()), "does not fit");
  // The receiver reader of `exao query --points` goes through CGAL's PLY reader too.
  const Result<std::vector<Receiver>> points = load_receivers((dir / "a.ply").string());
  ASSERT_FALSE(points.has_value());
  EXPECT_NE(points.error().message.find("no properties"), std::string::npos) << points.error().message;
}

TEST(HostileInput, PlyListLongerThanTheFileIsRefused) {
  test::TempDir dir;
  const std::string header = kPlyVertexHeader + "element face 1\nproperty list uint int vertex_indices\nend_header\n";
  test::write_file(dir / "ascii.ply", header + "0 0 0\n1 0 0\n0 1 0\n4000000000 0 1 2\n");
  expect_error(load_scene((dir / "ascii.ply").string()), "a list of 4000000000 items does not fit");

  std::string binary = "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                       "property float z\nelement face 1\nproperty list uint int vertex_indices\nend_header\n";
  const float xyz[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  binary.append(reinterpret_cast<const char*>(xyz), sizeof xyz);
  const std::uint32_t huge = 0xFFFFFFFFu;  // would be a 16 GB list
  binary.append(reinterpret_cast<const char*>(&huge), sizeof huge);
  const std::int32_t corners[3] = {0, 1, 2};
  binary.append(reinterpret_cast<const char*>(corners), sizeof corners);
  test::write_file(dir / "binary.ply", binary);
  expect_error(load_scene((dir / "binary.ply").string()), "a list of 4294967295 items does not fit");

  // The same file with a true count loads.
  const std::uint32_t three = 3;
  binary.replace(binary.size() - 16, 4, reinterpret_cast<const char*>(&three), 4);
  test::write_file(dir / "good.ply", binary);
  const Result<Scene> good = load_scene((dir / "good.ply").string());
  ASSERT_TRUE(good.has_value()) << good.error().message;
  EXPECT_EQ(good->triangle_count(), 1u);
}

// --- 3. OFF counts ------------------------------------------------------------------------------

TEST(HostileInput, OffFaceSizesAndBinaryCountsAreCheckedBeforeCgalAllocates) {
  test::TempDir dir;
  test::write_file(dir / "face.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n2000000000 0 1\n");
  expect_error(load_scene((dir / "face.off").string()), "face 0 says it has 2000000000");
  // A BINARY header over text data: its counts are the bytes of "3 1 0\n...", read as integers.
  test::write_file(dir / "binary.off", "OFF BINARY\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
  expect_error(load_scene((dir / "binary.off").string()), "do not fit");
  // Two colour numbers make CGAL read a third past its array.
  test::write_file(dir / "colour.off", "COFF\n3 1 0\n0 0 0 1 1\n1 0 0 1 1\n0 1 0 1 1\n3 0 1 2\n");
  expect_error(load_scene((dir / "colour.off").string()), "2 colour numbers");
  test::write_file(dir / "good.off", "OFF\n# a comment\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
  const Result<Scene> good = load_scene((dir / "good.off").string());
  ASSERT_TRUE(good.has_value()) << good.error().message;
  EXPECT_EQ(good->triangle_count(), 1u);
}

// --- 4. Buffer URIs that are not files -----------------------------------------------------------

TEST(HostileInput, BufferUriNamingAFolderOrAFifoIsRefusedByName) {
  test::TempDir dir;
  fs::create_directory(dir / "sub");
  for (const std::string uri : {"/", ".", "sub"}) {
    test::write_file(dir / "a.gltf", triangle_gltf("", "", uri));
    expect_error(load_scene((dir / "a.gltf").string()), "is a folder");
  }
  ASSERT_EQ(::mkfifo((dir / "pipe").c_str(), 0600), 0);
  test::write_file(dir / "a.gltf", triangle_gltf("", "", "pipe"));
  expect_error(load_scene((dir / "a.gltf").string()), "is a FIFO");  // and does not block
}

// --- 5. Cameras Embree cannot cast from ----------------------------------------------------------

TEST(HostileInput, NonFiniteOrHugeCamerasAreRefusedBeforeEmbree) {
  test::TempDir dir;
  const std::string out = " -W 8 -H 8 -o " + (dir / "a.exr").string() + " --png ''";
  expect_one_line_error(exao("render plane-pair --eye nan,0,5 --target 0,0,0" + out), "--eye");
  expect_one_line_error(exao("render plane-pair --eye 1e38,0,5 --target 0,0,0" + out), "--eye");
  expect_one_line_error(exao("render plane-pair --eye 0,0,5 --target inf,0,0" + out), "--target");
  test::write_file(dir / "far.gltf", triangle_gltf("", "", "", "\"translation\": [1e30, 0, 0]"));
  expect_one_line_error(exao("render " + (dir / "far.gltf").string() + out), "beyond");
  // A vertex out there is skipped like a non-finite one, with a note, and the rest renders.
  test::write_file(dir / "huge.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1e30 0 0\nf 1 2 3\nf 1 4 2\n");
  const CommandResult huge = exao("render " + (dir / "huge.obj").string() + out);
  EXPECT_EQ(huge.status, 0) << huge.output;
  EXPECT_NE(huge.output.find("skipped 1 triangles with NaN, infinite or huge"), std::string::npos) << huge.output;
}

TEST(HostileInput, CameraIndexBeyondEveryIntegerIsNoCamera) {
  test::TempDir dir;
  expect_one_line_error(exao("render plane-pair --camera 99999999999999999999 -W 8 -H 8 -o " + (dir / "a.exr").string() +
                             " --png ''"),
                        "no camera '99999999999999999999'");
}

// --- 6. Outputs that are not regular files -------------------------------------------------------

TEST(HostileInput, OutputsThatAreFifosOrFoldersAreRefusedAndLeftAlone) {
  test::TempDir dir;
  ASSERT_EQ(::mkfifo((dir / "pipe.exr").c_str(), 0600), 0);
  expect_one_line_error(exao("render plane-pair -W 8 -H 8 -o " + (dir / "pipe.exr").string() + " --png ''"), "is a FIFO");
  EXPECT_TRUE(fs::is_fifo(dir / "pipe.exr"));
  fs::create_directory(dir / "folder.txt");
  test::write_file(dir / "p.txt", "0 0 0 0 0 1\n");
  expect_one_line_error(exao("query --points " + (dir / "p.txt").string() + " -o " + (dir / "folder.txt").string()),
                        "is a folder");
  // A device node (made here, a copy of /dev/full's numbers, when the test may: root in a
  // container can) is refused the same way, never replaced by a regular file.
  if (::mknod((dir / "full.exr").c_str(), S_IFCHR | 0600, makedev(1, 7)) == 0) {
    expect_one_line_error(exao("render plane-pair -W 8 -H 8 -o " + (dir / "full.exr").string() + " --png ''"), "is a device");
    EXPECT_TRUE(fs::is_character_file(dir / "full.exr"));
  }
  // The library refuses them too, whoever calls it.
  bool called = false;
  const Result<void> written = write_atomically((dir / "pipe.exr").string(), [&](const std::string&) -> Result<void> {
    called = true;
    return {};
  });
  ASSERT_FALSE(written.has_value());
  EXPECT_FALSE(called);
  EXPECT_TRUE(fs::is_fifo(dir / "pipe.exr"));
}

TEST(HostileInput, SymlinkOutputsAreWrittenThroughAndKeptAsLinks) {
  test::TempDir dir;
  fs::create_directory(dir / "real");
  test::write_file(dir / "real" / "a.txt", "old\n");
  fs::create_symlink(dir / "real" / "a.txt", dir / "link.txt");
  test::write_file(dir / "p.txt", "0 0 1 0 0 1\n");
  const CommandResult run = exao("query --points " + (dir / "p.txt").string() + " -o " + (dir / "link.txt").string());
  ASSERT_EQ(run.status, 0) << run.output;
  EXPECT_TRUE(fs::is_symlink(dir / "link.txt"));
  EXPECT_NE(read_file(dir / "real" / "a.txt"), "old\n") << "the link's target holds the new values";
  EXPECT_EQ(std::distance(fs::directory_iterator(dir / "real"), {}), 1) << "no temporary file beside the target";

  fs::create_symlink(dir / "missing.txt", dir / "dangling.txt");
  expect_one_line_error(exao("query --points " + (dir / "p.txt").string() + " -o " + (dir / "dangling.txt").string()),
                        "missing file");
  ASSERT_EQ(::mkfifo((dir / "pipe").c_str(), 0600), 0);
  fs::create_symlink(dir / "pipe", dir / "to-pipe.txt");
  expect_one_line_error(exao("query --points " + (dir / "p.txt").string() + " -o " + (dir / "to-pipe.txt").string()),
                        "is a FIFO");
}

// --- 7. Temporary files of killed runs -----------------------------------------------------------

TEST(HostileInput, StaleTemporaryFilesOfDeadRunsAreRemovedAndLiveOnesKept) {
  test::TempDir dir;
  const pid_t child = ::fork();
  if (child == 0) ::_exit(0);
  ASSERT_GT(child, 0);
  ASSERT_EQ(::waitpid(child, nullptr, 0), child);  // a PID that is certainly dead now
  const fs::path dead = dir / (".a.txt.exao-partial-" + std::to_string(child));
  const fs::path live = dir / (".a.txt.exao-partial-" + std::to_string(::getpid()));
  const fs::path other = dir / (".b.txt.exao-partial-" + std::to_string(child));
  for (const fs::path& p : {dead, live, other}) test::write_file(p, "partial");
  test::write_file(dir / "p.txt", "0 0 1 0 0 1\n");
  const CommandResult run = exao("query --points " + (dir / "p.txt").string() + " -o " + (dir / "a.txt").string());
  ASSERT_EQ(run.status, 0) << run.output;
  EXPECT_FALSE(fs::exists(dead)) << "left by a dead run of the same output";
  EXPECT_TRUE(fs::exists(live)) << "its PID is alive: it may be writing";
  EXPECT_TRUE(fs::exists(other)) << "another output's";
}

// --- 8. Write errors say why ---------------------------------------------------------------------

TEST(HostileInput, WriteErrorsNameTheSystemsReason) {
  test::TempDir dir;
  // A file-size limit of zero: every write fails with EFBIG ("File too large"), as a full disk
  // fails with ENOSPC. SIGXFSZ is ignored so that the write returns the error.
  const std::string limit = "trap '' XFSZ; ulimit -f 0; ";
  const std::string reason = std::strerror(EFBIG);
  test::write_file(dir / "p.txt", "0 0 1 0 0 1\n");
  expect_one_line_error(exao("query --points " + (dir / "p.txt").string() + " -o " + (dir / "a.txt").string(), limit), reason);
  expect_one_line_error(exao("render plane-pair -W 8 -H 8 -o " + (dir / "a.exr").string() + " --png ''", limit), reason);
  expect_one_line_error(exao("bake plane-pair -o " + (dir / "a.glb").string(), limit), reason);
  EXPECT_EQ(std::distance(fs::directory_iterator(dir.path()), {}), 1) << "nothing left behind but the points";
}

// --- 9. Options out of range ---------------------------------------------------------------------

TEST(HostileInput, ThreadCountsOutOfRangeGetOneLine) {
  test::TempDir dir;
  const std::string out = " -W 8 -H 8 -o " + (dir / "a.exr").string() + " --png ''";
  expect_one_line_error(exao("render plane-pair --threads -5" + out), "--threads");
  expect_one_line_error(exao("render plane-pair --threads 100000" + out), "--threads");
  test::write_file(dir / "p.txt", "0 0 1 0 0 1\n");
  expect_one_line_error(exao("query --threads -5 --points " + (dir / "p.txt").string() + " -o " + (dir / "a.txt").string()),
                        "--threads");
  // More threads than the machine has is legal (and gives the same answer): a note says so.
  const unsigned more = std::thread::hardware_concurrency() + 1;
  const CommandResult run = exao("render plane-pair --threads " + std::to_string(more) + out);
  EXPECT_EQ(run.status, 0) << run.output;
  EXPECT_NE(run.output.find("note: --threads"), std::string::npos) << run.output;
}

TEST(HostileInput, AbsurdRadiiGetALineOrANote) {
  test::TempDir dir;
  const std::string out = " -W 8 -H 8 -o " + (dir / "a.exr").string() + " --png ''";
  expect_one_line_error(exao("render plane-pair --radius 1e30" + out), "--radius");
  const CommandResult large = exao("render plane-pair --radius 1e6" + out);
  EXPECT_EQ(large.status, 0) << large.output;
  EXPECT_NE(large.output.find("times the scene's diagonal"), std::string::npos) << large.output;
  const CommandResult tiny = exao("render plane-pair --radius 1e-9" + out);
  EXPECT_EQ(tiny.status, 0) << tiny.output;
  EXPECT_NE(tiny.output.find("ray origin offset"), std::string::npos) << tiny.output;
  test::write_file(dir / "p.txt", "0 0 1 0 0 1\n");
  const CommandResult query = exao("query --radius 1e6 --points " + (dir / "p.txt").string() + " -o " + (dir / "a.txt").string());
  EXPECT_EQ(query.status, 0) << query.output;
  EXPECT_NE(query.output.find("times the scene's diagonal"), std::string::npos) << query.output;
}

TEST(HostileInput, QueryPointsBeyondTheCoordinateLimitAreRefused) {
  test::TempDir dir;
  test::write_file(dir / "p.txt", "1e30 0 1 0 0 1\n");
  expect_one_line_error(exao("query --method embree --points " + (dir / "p.txt").string() + " -o " + (dir / "a.txt").string()),
                        "line 1");
}

// --- 10. Inputs that are not files ---------------------------------------------------------------

TEST(HostileInput, InfoSaysWhatAFolderOrAFifoIs) {
  test::TempDir dir;
  fs::create_directory(dir / "scene.glb");
  expect_one_line_error(exao("info " + (dir / "scene.glb").string()), "is a folder");
  ASSERT_EQ(::mkfifo((dir / "pipe.obj").c_str(), 0600), 0);
  expect_one_line_error(exao("info " + (dir / "pipe.obj").string()), "is a FIFO");  // and does not block
  ASSERT_EQ(::mkfifo((dir / "points.txt").c_str(), 0600), 0);
  expect_one_line_error(exao("query --points " + (dir / "points.txt").string() + " -o " + (dir / "a.txt").string()),
                        "is a FIFO");
}

}  // namespace
}  // namespace exao
