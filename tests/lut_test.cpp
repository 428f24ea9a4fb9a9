// The plane table: every cell holds the exact mask of the plane it stands for, the address maps
// a cell's plane back to the cell, and saved tables load back only for the pattern they pin.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "core/random.h"
#include "core/sample_pattern.h"
#include "lut/plane_table.h"
#include "tests/test_support.h"

namespace exao::lut {
namespace {

SamplePattern pattern_of(int n, Falloff falloff = Falloff::Linear, std::uint64_t seed = kDefaultPatternSeed) {
  auto pattern = make_sample_pattern(n, falloff, seed);
  EXPECT_TRUE(pattern) << pattern.error().message;
  return *pattern;
}

// The definition a cell must equal, written independently of the table's kernels: one scalar
// positive-side test per sample.
template <int Bits>
Mask<Bits> reference_mask(const SamplePattern& pattern, TableKind kind, const Plane& plane) {
  Mask<Bits> m;
  for (int i = 0; i < pattern.count; ++i) {
    const glm::vec3 s = kind == TableKind::Points ? pattern.points[i] : pattern.directions[i];
    if (on_positive_side(plane, s)) m.set(i);
  }
  return m;
}

template <int Bits>
void expect_cells_exact(const PlaneTable& table, const SamplePattern& pattern, std::size_t stride, std::uint64_t seed) {
  Rng rng(seed);
  std::size_t checked = 0;
  for (std::size_t i = 0; i < table.cell_count(); i += stride) {
    const std::size_t cell = stride == 1 ? i : rng.below(static_cast<std::uint32_t>(table.cell_count()));
    const Plane plane = table.cell_plane(cell);
    ASSERT_EQ(table.cell<Bits>(cell), reference_mask<Bits>(pattern, table.kind(), plane)) << "cell " << cell;
    ++checked;
  }
  EXPECT_GT(checked, 0u);
}

TEST(PlaneTable, EveryCellIsTheExactMaskOfItsPlaneExhaustive) {
  const SamplePattern pattern = pattern_of(64);
  for (const TableKind kind : {TableKind::Points, TableKind::Directions}) {
    auto table = PlaneTable::build(pattern, kind, 16);
    ASSERT_TRUE(table) << table.error().message;
    EXPECT_EQ(table->cell_count(), 16u * 16u * 16u);
    EXPECT_EQ(table->memory_bytes(), 16u * 16u * 16u * 8u);
    expect_cells_exact<64>(*table, pattern, 1, 0);
  }
}

TEST(PlaneTable, EveryCellIsTheExactMaskOfItsPlaneSampledAtDefaultResolution) {
  for (const int n : {128, 1024}) {
    const SamplePattern pattern = pattern_of(n);
    auto table = PlaneTable::build(pattern, TableKind::Points);
    ASSERT_TRUE(table) << table.error().message;
    EXPECT_EQ(table->resolution(), default_table_resolution(n));
    with_mask_bits(n, [&](auto bits) {
      expect_cells_exact<decltype(bits)::value>(*table, pattern, table->cell_count() / 3000, 17);
    });
  }
}

TEST(PlaneTable, DefaultMemoryIsTensOfMiB) {
  for (const int n : {32, 64, 128, 256, 512, 1024}) {
    const int r = default_table_resolution(n);
    const double mib = static_cast<double>(r) * r * r * mask_bits_for(n) / 8.0 / (1024.0 * 1024.0);
    EXPECT_GE(mib, 8.0) << n;
    EXPECT_LE(mib, 40.0) << n;
    RecordProperty("lut_mib_n" + std::to_string(n), std::to_string(mib));
  }
}

TEST(PlaneTable, AddressFollowsThePaper) {
  const SamplePattern pattern = pattern_of(64);
  auto table = PlaneTable::build(pattern, TableKind::Points, 16);
  ASSERT_TRUE(table);
  const auto r = static_cast<std::size_t>(table->resolution());
  // Every interior cell's own plane addresses that cell.
  for (std::size_t cell = 0; cell < table->cell_count(); ++cell) {
    if (table->in_outer_shell(cell)) continue;
    const Plane p = table->cell_plane(cell);
    if (p.d > 1.0f) continue;  // the unused core (d_norm < 1/8): no triangle plane lands there
    EXPECT_EQ(table->cell_index(p.m, p.d), cell) << cell;
  }
  // Every shell cell's plane has d = 0 and addresses that cell (the middle of its surface patch).
  for (std::size_t cell = 0; cell < table->cell_count(); ++cell) {
    if (!table->in_outer_shell(cell)) continue;
    const Plane p = table->cell_plane(cell);
    EXPECT_EQ(p.d, 0.0f);
    const std::size_t x = cell % r, y = cell / r % r, z = cell / (r * r);
    const bool face_only = (x == 0 || x == r - 1) + (y == 0 || y == r - 1) + (z == 0 || z == r - 1) == 1;
    if (face_only) {
      EXPECT_EQ(table->cell_index(p.m, 0.0f), cell) << cell;
    }
  }
  // d = 0 always lands in the shell; d = r lands 1/8 of the way out from the centre.
  Rng rng(5);
  for (int i = 0; i < 1000; ++i) {
    const glm::vec3 m = glm::normalize(glm::vec3(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5));
    EXPECT_TRUE(table->in_outer_shell(table->cell_index(m, 0.0f)));
    EXPECT_FALSE(table->in_outer_shell(table->cell_index(m, 1.0f)));
  }
  // The axes: +x at d = 0 is the middle of the +x face.
  EXPECT_EQ(table->cell_index({1.0f, 0.0f, 0.0f}, 0.0f), (8 * r + 8) * r + (r - 1));
  EXPECT_EQ(table->cell_index({0.0f, 0.0f, -1.0f}, 0.0f), (0 * r + 8) * r + 8);
}

TEST(PlaneTable, PatternHashSeesEveryFloat) {
  const SamplePattern a = pattern_of(64);
  SamplePattern b = a;
  EXPECT_EQ(pattern_hash(a), pattern_hash(b));
  b.lengths[17] = std::nextafter(b.lengths[17], 0.0f);
  EXPECT_NE(pattern_hash(a), pattern_hash(b));
  b = a;
  b.directions[63].x = std::nextafter(b.directions[63].x, 1.0f);
  EXPECT_NE(pattern_hash(a), pattern_hash(b));
  EXPECT_NE(pattern_hash(a), pattern_hash(pattern_of(64, Falloff::Linear, 7)));
  EXPECT_NE(pattern_hash(a), pattern_hash(pattern_of(64, Falloff::Constant)));
}

TEST(PlaneTable, RefusesBadResolution) {
  const SamplePattern pattern = pattern_of(64);
  auto table = PlaneTable::build(pattern, TableKind::Points, 2);
  ASSERT_FALSE(table);
  EXPECT_NE(table.error().message.find("2"), std::string::npos);
  EXPECT_FALSE(PlaneTable::build(pattern, TableKind::Points, 100000));
}

class PlaneTableFile : public ::testing::Test {
 protected:
  void SetUp() override {
    pattern_ = pattern_of(64);
    auto table = PlaneTable::build(pattern_, TableKind::Points, 16);
    ASSERT_TRUE(table);
    table_ = std::move(*table);
    path_ = (dir_ / "table.lut").string();
    auto saved = table_.save(path_);
    ASSERT_TRUE(saved) << saved.error().message;
  }

  std::string read() const {
    std::ifstream in(path_, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  }

  // Loads `path_` expecting `pattern`, `kind`, `resolution`, and checks that it is refused with a
  // one-line message naming the file and containing `why`.
  void expect_refused(const SamplePattern& pattern, TableKind kind, int resolution, const std::string& why) {
    auto loaded = PlaneTable::load(path_, pattern, kind, resolution);
    ASSERT_FALSE(loaded) << "accepted, expected: " << why;
    const std::string& message = loaded.error().message;
    EXPECT_EQ(message.rfind(path_, 0), 0u) << message;
    EXPECT_NE(message.find(why), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }

  test::TempDir dir_;
  SamplePattern pattern_;
  PlaneTable table_;
  std::string path_;
};

TEST_F(PlaneTableFile, RoundTrip) {
  auto loaded = PlaneTable::load(path_, pattern_, TableKind::Points, 16);
  ASSERT_TRUE(loaded) << loaded.error().message;
  EXPECT_EQ(loaded->resolution(), 16);
  EXPECT_EQ(loaded->samples(), 64);
  EXPECT_EQ(loaded->pattern_hash(), pattern_hash(pattern_));
  for (std::size_t cell = 0; cell < table_.cell_count(); ++cell) {
    ASSERT_EQ(loaded->cell<64>(cell), table_.cell<64>(cell));
  }
  // The file is the header plus exactly the masks.
  EXPECT_EQ(std::filesystem::file_size(path_), 72u + table_.memory_bytes());
}

TEST_F(PlaneTableFile, RefusesAnotherPattern) {
  expect_refused(pattern_of(128), TableKind::Points, 16, "N = 64");
  expect_refused(pattern_of(64, Falloff::Linear, 12345), TableKind::Points, 16, "another sample pattern");
  expect_refused(pattern_of(64, Falloff::Constant), TableKind::Points, 16, "another sample pattern");
  SamplePattern edited = pattern_;
  edited.lengths[3] *= 0.5f;
  edited.points[3] *= 0.5f;
  expect_refused(edited, TableKind::Points, 16, "another sample pattern");
}

TEST_F(PlaneTableFile, RefusesAnotherResolutionOrKind) {
  expect_refused(pattern_, TableKind::Points, 20, "resolution 16, expected 20");
  expect_refused(pattern_, TableKind::Points, 0, "resolution 16, expected 128");
  expect_refused(pattern_, TableKind::Directions, 16, "kind");
}

TEST_F(PlaneTableFile, RefusesDamagedFiles) {
  const std::string good = read();
  // A flipped bit in the masks.
  std::string bad = good;
  bad[good.size() / 2] = static_cast<char>(bad[good.size() / 2] ^ 0x10);
  test::write_file(path_, bad);
  expect_refused(pattern_, TableKind::Points, 16, "checksum");
  // A flipped byte in the header (the resolution field).
  bad = good;
  bad[16] = static_cast<char>(bad[16] ^ 0x01);
  test::write_file(path_, bad);
  expect_refused(pattern_, TableKind::Points, 16, "checksum");
  // Truncated in the payload, and in the header.
  test::write_file(path_, good.substr(0, good.size() - 1000));
  expect_refused(pattern_, TableKind::Points, 16, "truncated");
  test::write_file(path_, good.substr(0, 40));
  expect_refused(pattern_, TableKind::Points, 16, "truncated");
  // Trailing bytes.
  test::write_file(path_, good + "x");
  expect_refused(pattern_, TableKind::Points, 16, "trailing");
  // Not a table at all, and an empty file.
  test::write_file(path_, "exao-sample-pattern 1\nsamples 64\n");
  expect_refused(pattern_, TableKind::Points, 16, "not an exao plane table");
  test::write_file(path_, "");
  expect_refused(pattern_, TableKind::Points, 16, "not an exao plane table");
  // A future format version: named before anything else is read.
  bad = good;
  bad[8] = 2;
  test::write_file(path_, bad);
  expect_refused(pattern_, TableKind::Points, 16, "format version 2");
  // Missing.
  std::filesystem::remove(path_);
  expect_refused(pattern_, TableKind::Points, 16, "cannot open");
}

}  // namespace
}  // namespace exao::lut
