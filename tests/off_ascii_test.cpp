// The ASCII OFF fast path (io/off_ascii_reader.h) against CGAL's reader (SoupPath::Cgal) on
// generated files: number spellings, comments and blank lines between lines, CRLF, fractional and
// out-of-range sizes and indices, short lines, and the headers it leaves to CGAL. Whatever the
// fast path takes must be CGAL's scene bit for bit; whatever it leaves must load (or fail, with
// the pre-scan's or CGAL's words) as CGAL says.

#include <gtest/gtest.h>

#include <cstdio>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "io/off_ascii_reader.h"
#include "io/polygon_soup_loader.h"
#include "tests/scene_equality.h"
#include "tests/test_support.h"

namespace exao {
namespace {

// Loads `text` both ways; returns whether the fast path took it.
bool check(const test::TempDir& dir, const std::string& text) {
  return test::expect_fast_path_as_cgal(dir, "t.off", text, [](const std::string& t) { return read_ascii_off(t); });
}

// A bumpy grid with quads, a degenerate triangle, a two-corner face and a vertex beyond the
// coordinate limit, vertices printed with `format`, lines ended by `eol`, a comment every
// `comment_every` lines (0: none).
std::string grid(const char* format, const char* eol, int comment_every) {
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
  std::string out = std::string("OFF") + eol + std::to_string(vertices) + " " + std::to_string(faces.size()) + " 0" + eol;
  int line = 0;
  const auto end_line = [&] {
    out += eol;
    if (comment_every != 0 && ++line % comment_every == 0) out += std::string("# a comment 1 2 3") + eol + eol + "  ";
  };
  char number[96];
  for (int v = 0; v < vertices; ++v) {
    const int i = v % (n + 1), j = v / (n + 1);
    std::snprintf(number, sizeof number, format, v == vertices - 1 ? 1e30 : i / 9.0, j / 7.0, ((i * 7 + j * 3) % 5) / 13.0 - 0.2);
    out += number;
    end_line();
  }
  for (const auto& f : faces) {
    out += std::to_string(f.size());
    for (const int i : f) {
      out += ' ';
      out += std::to_string(i);
    }
    end_line();
  }
  return out;
}

TEST(OffAscii, GeneratedGridsEqualCgal) {
  test::TempDir dir;
  for (const char* format : {"%.9g %.9g %.9g", "%.17g %.17g %.17g", "%e\t%e\t%e", "%+.4f %+.4f %+.4f 0.5 0.5",
                             "%.9g %.9g %.9g # trailing comment"})
    for (const char* eol : {"\n", "\r\n"})
      for (const int comment_every : {0, 7}) {
        SCOPED_TRACE(std::string(format) + (eol[0] == '\r' ? " | CRLF" : "") + " | comments " + std::to_string(comment_every));
        EXPECT_TRUE(check(dir, grid(format, eol, comment_every))) << "the fast path left a common file to CGAL";
      }
}

TEST(OffAscii, ValuesAndHeadersAsCgalReadsThem) {
  test::TempDir dir;
  const std::string v = "0 0 0\n1 0 0\n1 1 0\n0 1 0.5\n";
  // Faces: fractional sizes and indices (truncated), signs, past the vertices, short lines,
  // comments cutting a line, a last line without its newline.
  for (const char* f : {"3 0 1 2\n3 0 2 3\n", "3.9 0 1 2\n3 0.5 2.99 3\n", "3 0 1 2\n3 0 2 4\n", "3 0 1 -2\n3 0 2 3\n",
                        "3 0 1\n3 0 2 3\n", "3 0 1 2 # 3\n3 0 2 # 3\n", "3 0 1 2\n3 0 2 3", "3 0 1 2 9 9 9\n3 0 2 3\n",
                        "3 0 1 x\n3 0 2 3\n", "1e0 0 1 2\n3 0 2 3\n", "3 0 1 2\n\n\n# c\n3 0 2 3\n", "-1 0 1 2\n3 0 2 3\n",
                        "3 0 1 2\n2 0 1\n", "1e300 0 1 2\n3 0 2 3\n"}) {
    SCOPED_TRACE(f);
    check(dir, "OFF\n4 2 0\n" + v + f);
  }
  // Vertices: spellings the stream takes and refuses, too few numbers.
  for (const char* x : {"+1 -0 .5", "5. 1e-3 1E+2", "1e-400 2 3", "1e 0 0", "inf 0 0", "1e999 0 0", "1 2", "1 2 # 3",
                        "x 0 0", "0x1 0 0"}) {
    SCOPED_TRACE(x);
    check(dir, std::string("OFF\n4 2 0\n") + x + "\n1 0 0\n1 1 0\n0 1 0.5\n3 0 1 2\n3 0 2 3\n");
  }
  // Headers and counts: on one line, comments, other keywords, counts CGAL or the pre-scan
  // refuse, a vertex line that ends the file.
  for (const std::string& text : std::vector<std::string>{
           "OFF 4 2 0\n" + v + "3 0 1 2\n3 0 2 3\n", "  OFF\n4 2 0\n" + v + "3 0 1 2\n", "# c\nOFF\n4 2 0\n" + v + "3 0 1 2\n",
           "OFF\n# c\n4 2 0\n" + v + "3 0 1 2\n", "COFF\n4 2 0\n" + v + "3 0 1 2\n", "NOFF\n4 1 0\n" + v + "3 0 1 2\n",
           "OFF\n4 -2 0\n" + v, "OFF\n-4 2 0\n" + v, "OFF\n4 2\n" + v, "OFF\n4000000 2 0\n" + v + "3 0 1 2\n",
           "OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0.5", "OFF\n4 0 0\n" + v, "OFFx\n4 2 0\n" + v + "3 0 1 2\n",
           "OFF\n4 2 0 junk\n" + v + "3 0 1 2\n3 0 2 3\n", "OFF\n4 2 0\n" + v + "3 0 1 2\n"}) {
    SCOPED_TRACE(text);
    check(dir, text);
  }
}

// Random lines over an awkward alphabet in a fixed header.
TEST(OffAscii, RandomFilesAnswerAsCgal) {
  test::TempDir dir;
  std::mt19937 rng(2123);
  const std::vector<std::string> numbers{"0", "1", "2", "3", "-1", "0.5", "-.25", "+2", "1e-3", "3.", "2.7", "1e-50"};
  const std::vector<std::string> bad{"1e", "x", "1e999", ".", "#", "9", "-3", "4"};
  const std::vector<std::string> separators{" ", " ", " ", "\t", "  ", "\r"};
  std::size_t taken = 0;
  for (int k = 0; k < 400; ++k) {
    std::string text = "OFF\n4 3 0\n";
    const auto token = [&] { return rng() % 10 == 0 ? bad[rng() % bad.size()] : numbers[rng() % numbers.size()]; };
    for (int v = 0; v < 4; ++v) {
      for (int c = 0, n = 2 + static_cast<int>(rng() % 3); c < n; ++c) {
        if (c != 0) text += separators[rng() % separators.size()];
        text += token();
      }
      text += rng() % 10 == 0 ? "\n# c\n" : "\n";
    }
    for (int f = 0; f < 3; ++f) {
      const int n = rng() % 6 == 0 ? static_cast<int>(rng() % 6) : 3;
      text += rng() % 10 == 0 ? token() : std::to_string(n);
      for (int i = 0; i < n + static_cast<int>(rng() % 2); ++i) {
        text += separators[rng() % separators.size()];
        text += rng() % 10 == 0 ? token() : std::to_string(rng() % 4);
      }
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
