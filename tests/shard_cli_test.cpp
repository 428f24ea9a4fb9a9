// Sharded jobs end to end (issue 25): `--shard K/N` on bake (texture and vertex), render and query,
// run as plain background processes, put together by `exao merge` and compared byte for byte with
// one unsharded run; --shard auto from a scheduler's variables; every kind of bad part refused in
// one line naming it, with nothing written; and `bake --resume` after a SIGKILL.

#include <gtest/gtest.h>

#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <random>
#include <regex>
#include <sstream>
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
using test::expect_one_line_error;

CommandResult sh(const std::string& command) { return test::run_command(command); }

// Built by append: GCC 12 warns (-Wrestrict, a false positive) on "'" + string + "'".
std::string quote(const fs::path& p) {
  std::string out(1, '\'');
  out.append(p.string());
  out.push_back('\'');
  return out;
}

std::string in_dir(const fs::path& dir, const std::string& arguments) {
  return "cd " + quote(dir) + " && " + std::string(EXAO_BINARY) + " " + arguments;
}

std::string read_bytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  EXPECT_TRUE(in) << path;
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void expect_same_file(const fs::path& a, const fs::path& b) {
  ASSERT_TRUE(fs::exists(a)) << a;
  ASSERT_TRUE(fs::exists(b)) << b;
  const std::string x = read_bytes(a), y = read_bytes(b);
  EXPECT_EQ(x.size(), y.size()) << a << " vs " << b;
  EXPECT_TRUE(x == y) << a << " and " << b << " differ";
}

// Runs `arguments --shard K/N` for every K at once as background processes of one shell, and
// returns what they printed (each prints "shard K/N: X of Y receivers ...").
std::string run_shards(const fs::path& dir, const std::string& arguments, int n) {
  std::string script = "cd " + quote(dir) + " && ( ";
  for (int k = 0; k < n; ++k) {
    script += std::string(EXAO_BINARY) + " " + arguments + " --shard " + std::to_string(k) + "/" + std::to_string(n) +
              " > shard" + std::to_string(k) + ".log 2>&1 & pids=\"$pids $!\"; ";
  }
  script += "fail=0; for pid in $pids; do wait $pid || fail=1; done; exit $fail )";
  const CommandResult result = sh(script);
  std::string logs;
  for (int k = 0; k < n; ++k) logs += read_bytes(dir / ("shard" + std::to_string(k) + ".log"));
  EXPECT_EQ(result.status, 0) << logs;
  return logs;
}

// The receivers each shard reported holding, in K order.
std::vector<long> shard_sizes(const std::string& logs, int n) {
  std::vector<long> sizes(static_cast<std::size_t>(n), -1);
  const std::regex line(R"(shard (\d+)/(\d+): (\d+) of (\d+) receivers)");
  for (std::sregex_iterator it(logs.begin(), logs.end(), line), end; it != end; ++it) {
    sizes[std::stoul((*it)[1])] = std::stol((*it)[3]);
  }
  return sizes;
}

std::string parts_of(const std::string& output, int n) {
  std::string out;
  for (int k = 0; k < n; ++k) {
    char suffix[64];
    std::snprintf(suffix, sizeof suffix, ".part-%04d-of-%04d.exao", k, n);
    out += " " + output + suffix;
  }
  return out;
}

// A texture bake of the room: one map (one material), so every boundary between shards is a
// seam inside that map, and dilation crosses it in merge. 512^2 texels x 4 samples make several
// 64k chunks, so all four shards compute some.
const std::string kTextureBake = "bake room --texture 512 -n 32 --preview ''";

TEST(Shard, TextureBakeOfFourProcessesMergesToTheBytesOfOneRun) {
  test::TempDir one, many;
  ASSERT_EQ(sh(in_dir(one.path(), kTextureBake + " -o room.glb")).status, 0);
  const std::string logs = run_shards(many.path(), kTextureBake + " -o room.glb", 4);
  const std::vector<long> sizes = shard_sizes(logs, 4);
  for (int k = 0; k < 4; ++k) EXPECT_GT(sizes[static_cast<std::size_t>(k)], 0) << "shard " << k << " computed nothing:\n" << logs;
  // A shard never writes the final outputs: a half-finished array leaves nothing that looks done.
  EXPECT_FALSE(fs::exists(many / "room.glb"));
  EXPECT_FALSE(fs::exists(many / "room_ao.png"));
  const CommandResult merged = sh(in_dir(many.path(), "merge" + parts_of("room.glb", 4) + " -o room.glb"));
  ASSERT_EQ(merged.status, 0) << merged.output;
  std::size_t files = 0;
  for (const auto& entry : fs::directory_iterator(one.path())) {
    expect_same_file(entry.path(), many / entry.path().filename());
    ++files;
  }
  EXPECT_GE(files, 3u);  // room.glb, room_ao.png, room_ao.exr
}

TEST(Shard, VertexBakeWithAnEmptyShardMergesToTheBytesOfOneRun) {
  // The room has fewer vertices than a chunk: one of the two parts is empty, and still a part.
  test::TempDir one, many;
  ASSERT_EQ(sh(in_dir(one.path(), "bake room --vertex -n 32 --preview '' -o room.glb")).status, 0);
  const std::vector<long> sizes = shard_sizes(run_shards(many.path(), "bake room --vertex -n 32 --preview '' -o room.glb", 2), 2);
  // One chunk: part K holds chunks [floor(K / 2), floor((K + 1) / 2)), so part 0 is the empty one.
  EXPECT_EQ(sizes[0], 0);
  EXPECT_GT(sizes[1], 0);
  const CommandResult merged = sh(in_dir(many.path(), "merge" + parts_of("room.glb", 2)));  // -o: the recorded one
  ASSERT_EQ(merged.status, 0) << merged.output;
  expect_same_file(one / "room.glb", many / "room.glb");
}

TEST(Shard, RenderOfThreeProcessesMergesToTheBytesOfOneRun) {
  test::TempDir one, many;
  const std::string render = "render room -W 512 -H 512 -n 32 --counts -o ao.exr --png ao.png";
  ASSERT_EQ(sh(in_dir(one.path(), render)).status, 0);
  const std::vector<long> sizes = shard_sizes(run_shards(many.path(), render, 3), 3);
  for (const long s : sizes) EXPECT_GT(s, 0);
  EXPECT_FALSE(fs::exists(many / "ao.exr"));
  const CommandResult merged = sh(in_dir(many.path(), "merge" + parts_of("ao.exr", 3) + " -o ao.exr"));
  ASSERT_EQ(merged.status, 0) << merged.output;
  expect_same_file(one / "ao.exr", many / "ao.exr");
  expect_same_file(one / "ao.png", many / "ao.png");
}

// 150,000 points over the room's floor and walls, so that the query has three chunks.
void write_points(const fs::path& path) {
  std::mt19937 rng(25);
  std::uniform_real_distribution<float> u(-0.9f, 0.9f);
  std::ofstream out(path);
  for (int i = 0; i < 150000; ++i) out << u(rng) << " " << u(rng) * 0.1f << " " << u(rng) << " 0 1 0\n";
}

TEST(Shard, QueryOfThreeProcessesMergesToTheBytesOfOneRun) {
  test::TempDir one, many;
  write_points(one / "points.txt");
  fs::copy_file(one / "points.txt", many / "points.txt");
  ASSERT_EQ(sh(in_dir(one.path(), "query room --points points.txt -n 32 -o ao.txt")).status, 0);
  const std::vector<long> sizes = shard_sizes(run_shards(many.path(), "query room --points points.txt -n 32 -o ao.txt", 3), 3);
  long total = 0;
  for (const long s : sizes) {
    EXPECT_GT(s, 0);
    total += s;
  }
  EXPECT_EQ(total, 150000);
  const CommandResult merged = sh(in_dir(many.path(), "merge" + parts_of("ao.txt", 3) + " -o merged.txt"));
  ASSERT_EQ(merged.status, 0) << merged.output;
  expect_same_file(one / "ao.txt", many / "merged.txt");
}

// Query parts for the error tests: three of a 150,000-point job, plus one made with other options.
class BadParts : public ::testing::Test {
 protected:
  void SetUp() override {
    write_points(dir / "points.txt");
    run_shards(dir.path(), "query room --points points.txt -n 32 -o ao.txt", 3);
    ASSERT_EQ(sh(in_dir(dir.path(), "query room --points points.txt -n 64 -o other.txt --shard 1/3")).status, 0);
    fs::rename(dir / "other.txt.part-0001-of-0003.exao", dir / "other-options.exao");
  }
  // merge `parts` -o out.txt: one line naming `names`, non-zero, and no output.
  void expect_refused(const std::string& parts, const std::string& names) {
    const CommandResult result = sh(in_dir(dir.path(), "merge " + parts + " -o out.txt"));
    expect_one_line_error(result, names);
    EXPECT_FALSE(fs::exists(dir / "out.txt"));
  }
  test::TempDir dir;
  const std::string p0 = "ao.txt.part-0000-of-0003.exao", p1 = "ao.txt.part-0001-of-0003.exao",
                    p2 = "ao.txt.part-0002-of-0003.exao";
};

TEST_F(BadParts, TheGoodOnesMerge) {
  const CommandResult result = sh(in_dir(dir.path(), "merge " + p0 + " " + p1 + " " + p2 + " -o out.txt"));
  EXPECT_EQ(result.status, 0) << result.output;
  EXPECT_TRUE(fs::exists(dir / "out.txt"));
}

TEST_F(BadParts, AMissingPartIsNamed) { expect_refused(p0 + " " + p2, p1); }

TEST_F(BadParts, ADuplicateIsNamed) {
  fs::copy_file(dir / p2, dir / "copy.exao");
  expect_refused(p0 + " " + p1 + " " + p2 + " copy.exao", "copy.exao");
}

TEST_F(BadParts, APartOfOtherOptionsIsNamed) { expect_refused(p0 + " other-options.exao " + p2, "other-options.exao"); }

TEST_F(BadParts, APartOfAnotherInputIsNamed) {
  // The same words over a points file with other contents: part 1 of another input.
  test::TempDir other;
  std::string points = read_bytes(dir / "points.txt");
  points[0] = points[0] == '-' ? '0' : '-';
  test::write_file(other / "points.txt", points);
  fs::remove(dir / p1);
  fs::copy_file(other / "points.txt", dir / "points.txt", fs::copy_options::overwrite_existing);
  ASSERT_EQ(sh(in_dir(dir.path(), "query room --points points.txt -n 32 -o ao.txt --shard 1/3")).status, 0);
  fs::rename(dir / p1, dir / "other-input.exao");
  expect_refused(p0 + " other-input.exao " + p2, "other-input.exao");
}

TEST_F(BadParts, ATruncatedPartIsNamed) {
  fs::resize_file(dir / p1, fs::file_size(dir / p1) - 100);
  expect_refused(p0 + " " + p1 + " " + p2, p1);
}

TEST_F(BadParts, ADamagedPartIsNamed) {
  std::string bytes = read_bytes(dir / p2);
  bytes[bytes.size() - 40] ^= 1;
  test::write_file(dir / p2, bytes);
  expect_refused(p0 + " " + p1 + " " + p2, p2);
}

TEST_F(BadParts, NotAPartIsNamed) { expect_refused(p0 + " " + p1 + " points.txt", "points.txt"); }

TEST_F(BadParts, AChangedInputIsNamed) {
  std::ofstream(dir / "points.txt", std::ios::app) << "0 0 0 0 1 0\n";
  expect_refused(p0 + " " + p1 + " " + p2, "points.txt");
}

TEST(ShardAuto, OutsideASchedulerIsAnErrorSayingSo) {
  test::TempDir dir;
  const CommandResult result =
      sh("cd " + quote(dir.path()) + " && env -u SLURM_ARRAY_TASK_ID -u JOB_COMPLETION_INDEX " + EXAO_BINARY +
         " bake room -n 32 --preview '' --shard auto");
  expect_one_line_error(result, "--shard auto");
  EXPECT_NE(result.output.find("SLURM_ARRAY_TASK_ID"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("JOB_COMPLETION_INDEX"), std::string::npos) << result.output;
  EXPECT_TRUE(fs::is_empty(dir.path()));
}

TEST(ShardAuto, TakesKAndNFromASlurmArray) {
  // Task 7 of --array=3-9:2 (tasks 3 5 7 9) is part 2 of 4.
  test::TempDir dir;
  const CommandResult result =
      sh("cd " + quote(dir.path()) + " && env -u JOB_COMPLETION_INDEX SLURM_ARRAY_TASK_ID=7 SLURM_ARRAY_TASK_MIN=3 "
         "SLURM_ARRAY_TASK_STEP=2 SLURM_ARRAY_TASK_COUNT=4 " + EXAO_BINARY + " bake room -n 32 --preview '' -o r.glb --shard auto");
  ASSERT_EQ(result.status, 0) << result.output;
  EXPECT_TRUE(fs::exists(dir / "r.glb.part-0002-of-0004.exao"));
  EXPECT_FALSE(fs::exists(dir / "r.glb"));
}

TEST(ShardAuto, TakesKFromAKubernetesIndexWithShardCount) {
  test::TempDir dir;
  const std::string env = "cd " + quote(dir.path()) + " && env -u SLURM_ARRAY_TASK_ID JOB_COMPLETION_INDEX=1 ";
  expect_one_line_error(sh(env + EXAO_BINARY + " bake room -n 32 --preview '' --shard auto"), "--shard-count");
  const CommandResult result = sh(env + EXAO_BINARY + " bake room -n 32 --preview '' -o r.glb --shard auto --shard-count 3");
  ASSERT_EQ(result.status, 0) << result.output;
  EXPECT_TRUE(fs::exists(dir / "r.glb.part-0001-of-0003.exao"));
}

TEST(ShardFlags, BadValuesAreOneLine) {
  test::TempDir dir;
  for (const std::string bad : {"4/4", "1", "a/3", "0/0", "-1/2"}) {
    expect_one_line_error(sh(in_dir(dir.path(), "bake room -n 32 --preview '' --shard " + bad)), "--shard");
  }
  expect_one_line_error(sh(in_dir(dir.path(), "render room -n 32 --method raster --shard 0/2")), "--shard");
  expect_one_line_error(sh(in_dir(dir.path(), "bench room --shard 0/2")), "--shard");
  EXPECT_TRUE(fs::is_empty(dir.path()));
}

TEST(ShardBench, TimesTheShardsReceiversOnly) {
  const CommandResult all = sh(std::string(EXAO_BINARY) + " bench room --receivers texels:512 -n 32 -r 5% --methods bvh --masks exact --shard 1/4");
  ASSERT_EQ(all.status, 0) << all.output;
  const std::vector<long> sizes = shard_sizes(all.output, 4);
  EXPECT_GT(sizes[1], 0);
  EXPECT_EQ(sizes[1] % 65536, 0);  // whole chunks, never the last (shorter) one for part 1 of 4
}

// bake --resume: killed with SIGKILL after its first chunk is kept, run again, the same bytes.
TEST(Resume, AKilledBakeGoesOnWhereItStopped) {
  test::TempDir one, dir;
  const std::string bake = "bake room --texture 512 -n 32 --preview '' -o room.glb";
  ASSERT_EQ(sh(in_dir(one.path(), bake)).status, 0);
  const fs::path chunks = dir / "chunks";
  const std::string out = (dir / "room.glb").string(), resume = chunks.string();
  std::vector<std::string> args = {EXAO_BINARY, "bake", "room", "--texture", "512", "-n", "32", "--preview", "",
                                   "-o", out, "--resume", resume};
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  pid_t child = 0;
  ASSERT_EQ(::posix_spawn(&child, EXAO_BINARY, nullptr, nullptr, argv.data(), environ), 0);
  // Waits for the first finished chunk (no clock in the check: the bound only ends a hung run).
  const auto parts = [&] {
    std::size_t n = 0;
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(chunks, ec)) n += e.path().extension() == ".exao" && e.path().filename().string()[0] != '.';
    return n;
  };
  for (int i = 0; i < 60000 && parts() == 0; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  ::kill(child, SIGKILL);
  int status = 0;
  ::waitpid(child, &status, 0);
  ASSERT_TRUE(WIFSIGNALED(status)) << "the bake finished before it was killed";
  const std::size_t kept = parts();
  ASSERT_GT(kept, 0u);
  EXPECT_FALSE(fs::exists(out));
  // The same words in the same folder: a part's job is its command line and folder.
  const CommandResult resumed = sh(std::string(EXAO_BINARY) + " bake room --texture 512 -n 32 --preview '' -o " + quote(out) +
                                   " --resume " + quote(chunks));
  ASSERT_EQ(resumed.status, 0) << resumed.output;
  std::smatch m;
  ASSERT_TRUE(std::regex_search(resumed.output, m, std::regex(R"(resumed (\d+) of (\d+) chunks)"))) << resumed.output;
  EXPECT_GE(std::stoul(m[1]), kept);
  EXPECT_LT(std::stoul(m[1]), std::stoul(m[2]));
  expect_same_file(one / "room.glb", dir / "room.glb");
  expect_same_file(one / "room_ao.png", dir / "room_ao.png");
  expect_same_file(one / "room_ao.exr", dir / "room_ao.exr");
}

TEST(Resume, AFolderOfAnotherBakeIsRefused) {
  test::TempDir dir;
  ASSERT_EQ(sh(in_dir(dir.path(), "bake room -n 32 --preview '' -o a.glb --resume chunks")).status, 0);
  const CommandResult other = sh(in_dir(dir.path(), "bake room -n 64 --preview '' -o b.glb --resume chunks"));
  expect_one_line_error(other, "chunks/");
  EXPECT_FALSE(fs::exists(dir / "b.glb"));
}

}  // namespace
}  // namespace exao
