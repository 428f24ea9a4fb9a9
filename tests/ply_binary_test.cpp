// The binary PLY fast path (io/ply_binary_reader.h) against CGAL's reader on the same mesh
// written as ASCII (which CGAL reads), and truncated or dangling binary files refused.

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "io/ply_binary_reader.h"
#include "io/polygon_soup_loader.h"
#include "tests/scene_equality.h"
#include "tests/test_support.h"

namespace exao {
namespace {

struct Mesh {
  std::vector<float> xyz;                // three a vertex
  std::vector<std::vector<int>> faces;   // any sizes, including too small ones
};

// A bumpy grid in exact binary fractions, plus a quad, a degenerate triangle, a two-corner face
// and a triangle through a vertex beyond the coordinate limit.
Mesh make_mesh() {
  Mesh m;
  const int n = 12;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) m.xyz.insert(m.xyz.end(), {float(i) / 16.0f, float(j) / 16.0f, float((i * 7 + j * 3) % 5) / 32.0f});
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int a = j * (n + 1) + i;
      if ((i + j) % 7 == 0) {
        m.faces.push_back({a, a + 1, a + n + 2, a + n + 1});  // a quad: fanned
      } else {
        m.faces.push_back({a, a + 1, a + n + 2});
        m.faces.push_back({a, a + n + 2, a + n + 1});
      }
    }
  m.faces.push_back({0, 1, 2});  // collinear: zero area
  m.faces.push_back({3, 4});     // too small
  const int far = static_cast<int>(m.xyz.size() / 3);
  m.xyz.insert(m.xyz.end(), {1e30f, 0.0f, 0.0f});
  m.faces.push_back({0, far, n + 1});
  return m;
}

template <class T>
void put(std::string& out, T value, bool big_endian) {
  char b[sizeof(T)];
  std::memcpy(b, &value, sizeof(T));
  if (big_endian != (std::endian::native == std::endian::big)) std::reverse(b, b + sizeof(T));
  out.append(b, sizeof(T));
}

// Binary, with an extra vertex property before x and (`flags`) a face property after the list;
// without it, and with int or uint indices, the face entries are the common layout the reader
// takes without its per-value switch.
std::string binary_ply(const Mesh& m, bool big_endian, bool doubles, bool flags = true, bool unsigned_indices = false) {
  const char* type = doubles ? "double" : "float";
  std::string out = std::string("ply\nformat ") + (big_endian ? "binary_big_endian" : "binary_little_endian") +
                    " 1.0\ncomment written by ply_binary_test\nelement vertex " + std::to_string(m.xyz.size() / 3) +
                    "\nproperty uchar red\nproperty " + type + " x\nproperty " + type + " y\nproperty " + type +
                    " z\nelement face " + std::to_string(m.faces.size()) +
                    "\nproperty list uchar " + (unsigned_indices ? "uint" : "int") + " vertex_indices\n" +
                    (flags ? "property ushort flags\n" : "") + "end_header\n";
  for (std::size_t v = 0; v < m.xyz.size() / 3; ++v) {
    put<std::uint8_t>(out, 200, big_endian);
    for (int k = 0; k < 3; ++k) {
      if (doubles) put<double>(out, m.xyz[3 * v + k], big_endian);
      else put<float>(out, m.xyz[3 * v + k], big_endian);
    }
  }
  for (const auto& f : m.faces) {
    put<std::uint8_t>(out, static_cast<std::uint8_t>(f.size()), big_endian);
    for (const int i : f) put<std::int32_t>(out, i, big_endian);  // the same bytes as uint for these indices
    if (flags) put<std::uint16_t>(out, 7, big_endian);
  }
  return out;
}

std::string ascii_ply(const Mesh& m) {
  std::string out = "ply\nformat ascii 1.0\nelement vertex " + std::to_string(m.xyz.size() / 3) +
                    "\nproperty float x\nproperty float y\nproperty float z\nelement face " + std::to_string(m.faces.size()) +
                    "\nproperty list uchar int vertex_indices\nend_header\n";
  char line[128];
  for (std::size_t v = 0; v < m.xyz.size() / 3; ++v) {
    std::snprintf(line, sizeof line, "%.9g %.9g %.9g\n", double(m.xyz[3 * v]), double(m.xyz[3 * v + 1]), double(m.xyz[3 * v + 2]));
    out += line;
  }
  for (const auto& f : m.faces) {
    out += std::to_string(f.size());
    for (const int i : f) {
      out += ' ';
      out += std::to_string(i);
    }
    out += '\n';
  }
  return out;
}

TEST(PlyBinary, FastPathEqualsCgalsReader) {
  const Mesh mesh = make_mesh();
  test::TempDir dir;
  test::write_file(dir / "ascii.ply", ascii_ply(mesh));
  const std::string ascii_bytes = ascii_ply(mesh);
  EXPECT_FALSE(read_binary_ply(ascii_bytes).has_value()) << "ASCII is not the binary reader's";
  const Result<Scene> reference = load_polygon_soup((dir / "ascii.ply").string(), {}, SoupPath::Cgal);
  ASSERT_TRUE(reference.has_value()) << reference.error().message;
  EXPECT_EQ(reference->report.zero_area_skipped, 1u);
  EXPECT_EQ(reference->report.non_finite_skipped, 1u);
  EXPECT_EQ(reference->report.notes.size(), 1u);

  for (const bool big_endian : {false, true})
    for (const bool doubles : {false, true})
      for (const int faces : {0, 1, 2}) {  // with flags; plain int; plain uint
        SCOPED_TRACE(std::string(big_endian ? "big" : "little") + " endian, " + (doubles ? "double" : "float") + ", faces " +
                     std::to_string(faces));
        const std::string bytes = binary_ply(mesh, big_endian, doubles, faces == 0, faces == 2);
        std::optional<Result<Scene>> direct = read_binary_ply(bytes);
        ASSERT_TRUE(direct.has_value()) << "this layout takes the fast path";
        ASSERT_TRUE(direct->has_value()) << direct->error().message;
        test::expect_same_scene(**direct, *reference);
        test::write_file(dir / "binary.ply", bytes);
        const Result<Scene> loaded = load_polygon_soup((dir / "binary.ply").string());
        ASSERT_TRUE(loaded.has_value()) << loaded.error().message;
        test::expect_same_scene(*loaded, *reference);
      }
}

TEST(PlyBinary, TruncatedOrDanglingFilesAreRefused) {
  for (const bool flags : {true, false}) {
    SCOPED_TRACE(flags ? "faces with flags" : "plain faces");
    const Mesh mesh = make_mesh();
    const std::string bytes = binary_ply(mesh, false, false, flags);
    test::TempDir dir;
    // Cut anywhere in the data: the loader names the file and the problem; the fast path alone
    // (no pre-scan) refuses rather than reads past the end.
    const std::size_t header = bytes.find("end_header\n") + 11;
    for (const std::size_t cut : {header + 5, header + 200, bytes.size() - 40, bytes.size() - 1}) {
      SCOPED_TRACE("cut at " + std::to_string(cut));
      const std::string truncated = bytes.substr(0, cut);
      test::write_file(dir / "cut.ply", truncated);
      const Result<Scene> loaded = load_polygon_soup((dir / "cut.ply").string());
      ASSERT_FALSE(loaded.has_value());
      EXPECT_NE(loaded.error().message.find("cut.ply: "), std::string::npos) << loaded.error().message;
      EXPECT_EQ(loaded.error().message.find('\n'), std::string::npos);
      const std::optional<Result<Scene>> direct = read_binary_ply(truncated);
      ASSERT_TRUE(direct.has_value());
      EXPECT_FALSE(direct->has_value());
    }
    // A face index past the vertices: the same words as the CGAL path's.
    Mesh dangling = mesh;
    dangling.faces[1] = {0, 1, 9999};
    test::write_file(dir / "dangling.ply", binary_ply(dangling, false, false, flags));
    test::write_file(dir / "dangling-ascii.ply", ascii_ply(dangling));
    const Result<Scene> fast = load_polygon_soup((dir / "dangling.ply").string());
    const Result<Scene> cgal = load_polygon_soup((dir / "dangling-ascii.ply").string(), {}, SoupPath::Cgal);
    ASSERT_FALSE(fast.has_value());
    ASSERT_FALSE(cgal.has_value());
    const std::string vertices = std::to_string(dangling.xyz.size() / 3);
    EXPECT_NE(fast.error().message.find("face 2 refers to vertex 9999, file has " + vertices), std::string::npos) << fast.error().message;
    const std::string& a = fast.error().message;
    const std::string& b = cgal.error().message;
    EXPECT_EQ(std::string_view(a).substr(a.find(": ")), std::string_view(b).substr(b.find(": ")));
  }
}

}  // namespace
}  // namespace exao
