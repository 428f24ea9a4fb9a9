// The binary STL fast path (io/stl_binary_reader.h) against CGAL's reader on the same facets
// written as ASCII, and the files it must leave to CGAL (ASCII, truncated, -0 or NaN corners).

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "io/polygon_soup_loader.h"
#include "io/stl_binary_reader.h"
#include "tests/scene_equality.h"
#include "tests/test_support.h"

namespace exao {
namespace {

using Facet = std::array<float, 9>;

// A bumpy grid in exact binary fractions (shared corners, as a real STL repeats them), a
// degenerate facet and one through a vertex beyond the coordinate limit.
std::vector<Facet> make_facets() {
  std::vector<Facet> facets;
  const int n = 10;
  const auto z = [](int i, int j) { return float((i * 7 + j * 3) % 5) / 32.0f; };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const float x0 = float(i) / 16.0f, x1 = float(i + 1) / 16.0f, y0 = float(j) / 16.0f, y1 = float(j + 1) / 16.0f;
      facets.push_back({x0, y0, z(i, j), x1, y0, z(i + 1, j), x1, y1, z(i + 1, j + 1)});
      facets.push_back({x0, y0, z(i, j), x1, y1, z(i + 1, j + 1), x0, y1, z(i, j + 1)});
    }
  facets.push_back({0.5f, 0.5f, 0.5f, 0.5f, 0.5f, 0.5f, 1.0f, 1.0f, 1.0f});  // zero area
  facets.push_back({0.0f, 0.25f, 0.0f, 1e30f, 0.25f, 0.0f, 0.0f, 0.5f, 0.0f});  // beyond the limit
  return facets;
}

void put_float(std::string& out, float value) {
  std::uint32_t bits = 0;
  std::memcpy(&bits, &value, 4);
  for (int i = 0; i < 4; ++i) out += static_cast<char>((bits >> (8 * i)) & 0xFF);
}

std::string binary_stl(const std::vector<Facet>& facets, const std::string& header = "binary STL by stl_binary_test") {
  std::string out = header;
  out.resize(80, ' ');
  const auto count = static_cast<std::uint32_t>(facets.size());
  for (int i = 0; i < 4; ++i) out += static_cast<char>((count >> (8 * i)) & 0xFF);
  for (const Facet& f : facets) {
    for (int k = 0; k < 3; ++k) put_float(out, 0.0f);  // the normal, which readers ignore
    for (const float x : f) put_float(out, x);
    out += std::string(2, '\0');
  }
  return out;
}

std::string ascii_stl(const std::vector<Facet>& facets) {
  std::string out = "solid test\n";
  char line[160];
  for (const Facet& f : facets) {
    out += "facet normal 0 0 1\nouter loop\n";
    for (int k = 0; k < 3; ++k) {
      std::snprintf(line, sizeof line, "vertex %.9g %.9g %.9g\n", double(f[3 * k]), double(f[3 * k + 1]), double(f[3 * k + 2]));
      out += line;
    }
    out += "endloop\nendfacet\n";
  }
  return out + "endsolid test\n";
}

TEST(StlBinary, FastPathEqualsCgalsReader) {
  const std::vector<Facet> facets = make_facets();
  test::TempDir dir;
  const std::string ascii = ascii_stl(facets);
  EXPECT_FALSE(read_binary_stl(ascii).has_value()) << "ASCII goes to CGAL";
  test::write_file(dir / "ascii.stl", ascii);
  const Result<Scene> reference = load_polygon_soup((dir / "ascii.stl").string(), {}, SoupPath::Cgal);
  ASSERT_TRUE(reference.has_value()) << reference.error().message;
  EXPECT_EQ(reference->report.zero_area_skipped, 1u);
  EXPECT_EQ(reference->report.non_finite_skipped, 1u);

  // A plain header, and one that starts "solid " as many exporters write it (CGAL tries ASCII,
  // finds no facet, and reads it as binary).
  for (const std::string header : {"binary STL by stl_binary_test", "solid exported"}) {
    SCOPED_TRACE(header);
    const std::string bytes = binary_stl(facets, header);
    std::size_t last_done = 0, last_total = 0;
    const std::optional<Result<Scene>> direct =
        read_binary_stl(bytes, [&](std::size_t done, std::size_t total) { last_done = done, last_total = total; });
    ASSERT_TRUE(direct.has_value()) << "a binary STL takes the fast path";
    ASSERT_TRUE(direct->has_value()) << direct->error().message;
    test::expect_same_scene(**direct, *reference);
    EXPECT_EQ(last_done, bytes.size());
    EXPECT_EQ(last_total, bytes.size());
    test::write_file(dir / "binary.stl", bytes);
    const Result<Scene> loaded = load_polygon_soup((dir / "binary.stl").string());
    ASSERT_TRUE(loaded.has_value()) << loaded.error().message;
    test::expect_same_scene(*loaded, *reference);
    // Bytes past the stated count are ignored, as CGAL ignores them.
    const std::optional<Result<Scene>> longer = read_binary_stl(bytes + "trailing");
    ASSERT_TRUE(longer.has_value() && longer->has_value());
    test::expect_same_scene(**longer, *reference);
  }
}

TEST(StlBinary, FilesCgalReadsOtherwiseAreLeftToIt) {
  const std::vector<Facet> facets = make_facets();
  // A "solid" header over data holding the word "facet": CGAL's ASCII parse may read from it.
  std::vector<Facet> plain = facets;
  EXPECT_FALSE(read_binary_stl(binary_stl(plain, "solid facet")).has_value());
  EXPECT_FALSE(read_binary_stl(binary_stl(plain, "solid x endsolid")).has_value());
  // Truncated (CGAL's binary read fails and it tries ASCII), and no facet at all.
  const std::string bytes = binary_stl(plain);
  EXPECT_FALSE(read_binary_stl(bytes.substr(0, bytes.size() - 1)).has_value());
  EXPECT_FALSE(read_binary_stl(binary_stl({})).has_value());
  EXPECT_FALSE(read_binary_stl(bytes.substr(0, 50)).has_value());
  // -0 and NaN corners: CGAL's vertex map merges them with other vertices.
  std::vector<Facet> signed_zero = facets;
  signed_zero[3][2] = -0.0f;
  EXPECT_FALSE(read_binary_stl(binary_stl(signed_zero)).has_value());
  std::vector<Facet> nan = facets;
  nan[5][4] = std::numeric_limits<float>::quiet_NaN();
  EXPECT_FALSE(read_binary_stl(binary_stl(nan)).has_value());
  // The loader still reads them, through CGAL.
  test::TempDir dir;
  test::write_file(dir / "zero.stl", binary_stl(signed_zero));
  const Result<Scene> loaded = load_polygon_soup((dir / "zero.stl").string());
  ASSERT_TRUE(loaded.has_value()) << loaded.error().message;
  EXPECT_EQ(loaded->report.triangles_read, facets.size());
}

}  // namespace
}  // namespace exao
