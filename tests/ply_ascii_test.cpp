// The ASCII PLY fast path (io/ply_ascii_reader.h) against CGAL's reader (SoupPath::Cgal) on
// generated files: float and double coordinates among other vertex properties, every count and
// index type, number spellings the stream takes and refuses, values across lines, and the layouts
// and values it leaves to CGAL. Whatever the fast path takes must be CGAL's scene bit for bit;
// whatever it leaves must load (or fail) as CGAL says.

#include <gtest/gtest.h>

#include <cstdio>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "io/ply_ascii_reader.h"
#include "io/polygon_soup_loader.h"
#include "tests/scene_equality.h"
#include "tests/test_support.h"

namespace exao {
namespace {

// Loads `text` both ways; returns whether the fast path took it.
bool check(const test::TempDir& dir, const std::string& text) {
  return test::expect_fast_path_as_cgal(dir, "t.ply", text, [](const std::string& t) { return read_ascii_ply(t); });
}

struct Layout {
  const char* coordinate = "float";                             // x, y, z
  const char* list = "list uchar int vertex_indices";
  bool extra = false;                                           // nx before x, red after z
  const char* format = "%.9g";
  const char* separator = " ";
  const char* eol = "\n";
};

// A bumpy grid with quads, a degenerate triangle, a two-corner face and a vertex beyond the
// coordinate limit (as ply_binary_test's mesh).
std::string grid(const Layout& l) {
  const int n = 8;
  const int vertices = (n + 1) * (n + 1) + 1;
  std::vector<std::vector<int>> faces;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int a = j * (n + 1) + i;
      if ((i + j) % 7 == 0) {
        faces.push_back({a, a + 1, a + n + 2, a + n + 1});
      } else {
        faces.push_back({a, a + 1, a + n + 2});
        faces.push_back({a, a + n + 2, a + n + 1});
      }
    }
  faces.push_back({0, 1, 2});
  faces.push_back({3, 4});
  faces.push_back({0, vertices - 1, n + 1});
  std::string out = std::string("ply") + l.eol + "format ascii 1.0" + l.eol + "comment ply_ascii_test" + l.eol +
                    "element vertex " + std::to_string(vertices) + l.eol;
  if (l.extra) out += std::string("property float nx") + l.eol;
  for (const char* axis : {"x", "y", "z"}) out += std::string("property ") + l.coordinate + " " + axis + l.eol;
  if (l.extra) out += std::string("property uchar red") + l.eol;
  out += "element face " + std::to_string(faces.size()) + l.eol + "property " + l.list + l.eol + "end_header" + l.eol;
  char number[64];
  const auto put = [&](double v) {
    std::snprintf(number, sizeof number, l.format, v);
    out += number;
  };
  for (int v = 0; v < vertices; ++v) {
    const int i = v % (n + 1), j = v / (n + 1);
    if (l.extra) out += "0.5" + std::string(l.separator);
    if (v == vertices - 1) {
      out += "1e30";
    } else {
      put(i / 9.0);
    }
    out += l.separator;
    put(j / 7.0);
    out += l.separator;
    put(((i * 7 + j * 3) % 5) / 13.0 - 0.2);
    if (l.extra) out += std::string(l.separator) + "200";
    out += l.eol;
  }
  for (const auto& f : faces) {
    out += std::to_string(f.size());
    for (const int i : f) out += std::string(l.separator) + std::to_string(i);
    out += l.eol;
  }
  return out;
}

TEST(PlyAscii, GeneratedGridsEqualCgal) {
  test::TempDir dir;
  for (const char* coordinate : {"float", "double", "float32", "float64"})
    for (const char* list : {"list uchar int vertex_indices", "list int uint vertex_indices", "list ushort int vertex_index",
                             "list uint8 uint32 vertex_indices"})
      for (const bool extra : {false, true})
        for (const char* format : {"%.9g", "%.17g", "%e", "%+.4f"})
          for (const char* separator : {" ", "\t", "  \n "})
            for (const char* eol : {"\n", "\r\n"}) {
              const Layout l{coordinate, list, extra, format, separator, eol};
              SCOPED_TRACE(std::string(coordinate) + " | " + list + (extra ? " | extra" : "") + " | " + format);
              EXPECT_TRUE(check(dir, grid(l))) << "the fast path left a common file to CGAL";
              if (::testing::Test::HasFailure()) return;
            }
}

TEST(PlyAscii, ValuesAndLayoutsLeftToCgal) {
  test::TempDir dir;
  const std::string head = "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n";
  const std::string tail = "element face 2\nproperty list uchar int vertex_indices\nend_header\n";
  const std::string faces = "3 0 1 2\n3 0 2 3\n";
  // Vertex values: taken by both, or refused by the stream, or beyond float (strtof gives inf).
  for (const char* v : {"0 0 0", "+1 -0 .5", "5. 1e-3 1E+2", "1e-46 1.4e-45 3.4028235e38", "3.5e38 0 0", "1e 0 0",
                        "inf 0 0", "nan 0 0", "x 0 0", "0x1p3 0 0", "1,5 0 0", "- 0 0"}) {
    SCOPED_TRACE(v);
    check(dir, head + tail + v + "\n1 0 0\n1 1 0\n0 1 0.5\n" + faces);
  }
  // Counts and indices: signs, wrap-arounds, past the vertices, too few, garbage.
  for (const char* f : {"3 0 1 2\n3 0 2 3\n", "3 0 1 2\n3 0 2 4\n", "3 0 1 -2\n3 0 2 3\n", "+3 0 1 2\n3 0 2 3\n",
                        "259 0 1 2\n3 0 2 3\n", "3 0 1\n", "3 0 1 2\n2 0 1\n", "3 0 1 2\n3 0 2 3 9 9 9\n",
                        "3 0 1 2 3 0 2 3", "3 0 1 2x 3 0 2 3\n", "0\n0\n", "3 0 1 2\n1 0\n"}) {
    SCOPED_TRACE(f);
    check(dir, head + tail + "0 0 0\n1 0 0\n1 1 0\n0 1 0.5\n" + f);
  }
  // Layouts the fast path does not take; CGAL decides.
  const std::string v4 = "0 0 0\n1 0 0\n1 1 0\n0 1 0.5\n";
  for (const std::string& text : std::vector<std::string>{
           "ply\nformat ascii 1.0\nelement vertices 4\nproperty float x\nproperty float y\nproperty float z\n" + tail + v4 + faces,
           head + "element face 2\nproperty list uchar uchar vertex_indices\nend_header\n" + v4 + faces,
           head + "element face 2\nproperty list uchar int vertex_indices\nproperty uchar flags\nend_header\n" + v4 +
               "3 0 1 2 7\n3 0 2 3 7\n",
           head + tail + "element edge 0\nproperty int a\n" + v4 + faces,
           "ply\nformat ascii 1.0\nelement vertex 4\nproperty int x\nproperty int y\nproperty int z\n" + tail +
               "0 0 0\n1 0 0\n1 1 0\n0 1 1\n" + faces,
           head + "element face 2\nproperty list uchar int vertex_indices\nend_header\n" + v4,  // no faces
       }) {
    SCOPED_TRACE(text);
    EXPECT_FALSE(check(dir, text));
  }
}

// CGAL's point reader dereferences a null pointer for coordinates that are neither float nor
// double (found by this test): the pre-scan refuses them, in ASCII and binary files alike.
TEST(PlyAscii, IntegerCoordinatesAreRefusedBeforeCgal) {
  test::TempDir dir;
  const std::string tail = "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
  for (const std::string& format : {std::string("ascii"), std::string("binary_little_endian")}) {
    for (const char* x : {"property int x", "property uchar x", "property list uchar float x"}) {
      SCOPED_TRACE(format + " | " + x);
      std::string text = "ply\nformat " + format + " 1.0\nelement vertex 3\n" + x +
                         "\nproperty float y\nproperty float z\n" + tail;
      text += format == "ascii" ? "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n" : std::string(64, '\0');
      const std::string path = (dir / "int.ply").string();
      test::write_file(path, text);
      for (const SoupPath reader : {SoupPath::Fast, SoupPath::Cgal}) {
        const Result<Scene> loaded = load_polygon_soup(path, {}, reader);
        ASSERT_FALSE(loaded.has_value());
        EXPECT_NE(loaded.error().message.find(path + ": header line 4: vertex coordinate 'x' is "), std::string::npos)
            << loaded.error().message;
      }
    }
  }
}

// Random values over an awkward alphabet in a fixed layout.
TEST(PlyAscii, RandomFilesAnswerAsCgal) {
  test::TempDir dir;
  std::mt19937 rng(2122);
  const std::vector<std::string> numbers{"0", "1", "-1", "0.5", "-.25", "+2", "1e-3", "3.", "2", "-0", "7E+1", "1e-50",
                                         "1e", "x", "1e99", ".", "255", "300"};
  const std::vector<std::string> separators{" ", " ", " ", "\n", "\t", "\r\n", "  "};
  std::size_t taken = 0;
  for (int k = 0; k < 400; ++k) {
    std::string text = "ply\nformat ascii 1.0\nelement vertex 5\nproperty float x\nproperty double y\nproperty float z\n"
                       "property uchar red\nelement face 3\nproperty list uchar int vertex_indices\nend_header\n";
    const auto token = [&](bool index) {
      if (index) return rng() % 12 == 0 ? numbers[rng() % numbers.size()] : std::to_string(rng() % 5);
      return rng() % 10 == 0 ? numbers[12 + rng() % 6] : numbers[rng() % 12];
    };
    for (int v = 0; v < 5; ++v) {
      for (int c = 0; c < 3; ++c) text += token(false) + separators[rng() % separators.size()];
      text += (rng() % 10 == 0 ? numbers[rng() % numbers.size()] : "7") + std::string("\n");
    }
    for (int f = 0; f < 3; ++f) {
      const int n = rng() % 8 == 0 ? static_cast<int>(rng() % 6) : 3;
      text += std::to_string(n);
      for (int i = 0; i < n; ++i) text += separators[rng() % separators.size()] + token(true);
      text += "\n";
    }
    SCOPED_TRACE(text);
    taken += check(dir, text) ? 1 : 0;
    if (::testing::Test::HasFailure()) break;
  }
  EXPECT_GT(taken, 15u) << "the alphabet should let the fast path take some files";
}

}  // namespace
}  // namespace exao
