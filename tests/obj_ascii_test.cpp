// The ASCII OBJ fast path (io/obj_ascii_reader.h) against CGAL's reader (SoupPath::Cgal) on
// generated files: the number spellings libstdc++'s stream takes and those it refuses, every face
// syntax (v, v/t, v//n, v/t/n, negative indices, polygons), CRLF and tabs, the statements CGAL
// ignores, and a few thousand random files from an awkward alphabet. Whatever the fast path
// takes must be CGAL's scene bit for bit; whatever it leaves must load (or fail) as CGAL says.

#include <gtest/gtest.h>

#include <cstdio>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "io/obj_ascii_reader.h"
#include "io/polygon_soup_loader.h"
#include "tests/scene_equality.h"
#include "tests/test_support.h"

namespace exao {
namespace {

// Loads `text` both ways (the same scene, or the same one-line error naming the file); returns
// whether the fast path took it.
bool check(const test::TempDir& dir, const std::string& text, const std::string& name = "t.obj") {
  return test::expect_fast_path_as_cgal(dir, name, text, [](const std::string& t) { return read_ascii_obj(t); });
}

// A bumpy grid, vertices printed with `format`, faces with `face` ("%d" per corner, or with
// texture and normal indices), some as quads.
std::string grid(const char* format, const char* corner, bool negative = false, const char* eol = "\n") {
  std::string out = "# grid\no grid\nmtllib none.mtl\nusemtl stone\ns off\n";
  char line[256];
  const int n = 9;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const double x = i / 9.0, y = j / 7.0, z = ((i * 7 + j * 3) % 5) / 13.0 - 0.2;
      std::snprintf(line, sizeof line, format, x, y, z);
      out += std::string("v ") + line + eol;
    }
  out += std::string("vt 0.5 0.5") + eol + "vn 0 0 1" + eol + "g faces" + eol;
  const int count = (n + 1) * (n + 1);
  const auto index = [&](int v) {
    std::snprintf(line, sizeof line, corner, negative ? v - count : v + 1);
    return std::string(line);
  };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int a = j * (n + 1) + i, b = a + 1, c = a + n + 1, d = a + n + 2;
      if ((i + j) % 5 == 0) {
        out += "f " + index(a) + " " + index(b) + " " + index(d) + " " + index(c) + eol;  // a quad: fanned
      } else {
        out += "f " + index(a) + " " + index(b) + " " + index(d) + eol;
        out += "f " + index(a) + " " + index(d) + " " + index(c) + eol;
      }
    }
  return out;
}

TEST(ObjAscii, GeneratedGridsEqualCgal) {
  test::TempDir dir;
  for (const char* format : {"%.9g %.9g %.9g", "%.17g %.17g %.17g", "%f %f %f", "%e %E %e", "%+.3f\t%+.3e  %.0f",
                             "%.6f %.6f %.6f 1.0", "%.25f %.30f %.40f"}) {
    for (const char* corner : {"%d", "%d/1", "%d//1", "%d/1/1"}) {
      for (const bool negative : {false, true}) {
        for (const char* eol : {"\n", "\r\n"}) {
          SCOPED_TRACE(std::string(format) + " | " + corner + (negative ? " | negative" : "") + (eol[0] == '\r' ? " | CRLF" : ""));
          EXPECT_TRUE(check(dir, grid(format, corner, negative, eol))) << "the fast path left a common file to CGAL";
        }
      }
    }
  }
}

TEST(ObjAscii, NumberSpellingsAsTheStreamTakesThem) {
  test::TempDir dir;
  const std::string faces = "f 1 2 3\nf 1 3 4\n";
  // Taken by both: exact ties, denormals, underflow to zero, long mantissas, odd but valid forms.
  for (const char* v : {"+1 -0 .5", "5. 0.0e0 1E-3", "4.9406564584124654e-324 2.2250738585072011e-308 1e-400",
                        "0.1000000000000000055511151231257827021181583404541015625 3.4028235677973366e38 -1.5",
                        "000001 0000.5000 -00.25e+01", "1e38 3.4028236e38 -3.4028235e38", "1.0000000596046448 1 1"}) {
    SCOPED_TRACE(v);
    const std::string text = std::string("v ") + v + "\nv 1 0 0\nv 1 1 0\nv 0 1 0.5\n" + faces;
    check(dir, text);
  }
  // Refused by the stream (CGAL's error), or read otherwise than a number parser would.
  for (const char* v : {"1e 0 0", "1e+ 0 0", ". 0 0", "- 0 0", "+-1 0 0", "1e999 0 0", "-1e400 0 0", "inf 0 0",
                        "nan 0 0", "0x10 0 0", "1,5 0 0", "1 2", "1 2 3e", "1 2 3e-", "1.2.3 0 0", "1ee5 0 0"}) {
    SCOPED_TRACE(v);
    const std::string text = std::string("v ") + v + "\nv 1 0 0\nv 1 1 0\nv 0 1 0.5\n" + faces;
    check(dir, text);
  }
}

TEST(ObjAscii, FaceSyntaxAsCgalReadsIt) {
  test::TempDir dir;
  const std::string v = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0.5 0.5 1\n";
  for (const std::string& f : std::vector<std::string>{
           "f 1 2 3\nf 1 3 4 5\n", "f 1/2/3 2/3/4 3/4/5\n", "f -5 -4 -3\n", "f 1 2 3 # a comment\n",
           "f 1 2 3 x 4\n", "f 1\t2\t3\n",  // tabs: CGAL skips to the next space, so one corner
           "f 1  2   3\n", "f  1 2 3 \n", "f 1 2\nf 3\nf\nf 1 2 3\n", "f +1 +2 +3\n", "f 0001 2 3\n",
           "f 1a 2b 3c\n", "f 1 2 3 4 5 1\n", "f 1 1 1\n",
           "f 1/" + std::string(300, 'x') + " 2 3 4\n",  // ignore() stops after 256 characters
           "f 2147483648 1 2\n", "f 1 2 -2147483648\n", "f 6 1 2\n", "f 0 1 2\n", "f -6 1 2\n",
           "f 1 2 3\nv 2 2 2\nf 6 1 2\n",  // a forward reference (CGAL: fine here)
           "f 1 2 3\nl 1 2\n", "f 1 2 3\nvv 1 2 3\n", "#\n\n   \n\t\nf 1 2 3"}) {
    SCOPED_TRACE(f);
    check(dir, v + f);
  }
  check(dir, "v 0 0 0\nv 1 0 0\nv 0 1 0\n");  // no face
  check(dir, "f 1 2 3\n");                    // no vertex
  check(dir, "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n");  // no triangle with area
  check(dir, "v 0 0 0\nv 1e30 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 1 3 4\n");  // beyond the coordinate limit
  check(dir, "");
}

// Random files over an alphabet of the tokens and separators that matter: whatever the fast path
// takes is CGAL's scene, and the loader answers as CGAL does.
TEST(ObjAscii, RandomFilesAnswerAsCgal) {
  test::TempDir dir;
  std::mt19937 rng(2121);
  const auto pick = [&](const std::vector<std::string>& from) { return from[rng() % from.size()]; };
  // Mostly what real files hold, with an awkward spelling one time in ten.
  const std::vector<std::string> numbers{"0", "1", "-1", "0.5", "-.25", "+2", "1e-3", "3.", "0.125", "2", "-0", "7E+1",
                                         "0.75", "1.5e-320", "1e-400"};
  const std::vector<std::string> bad_numbers{"1e", "x", "1e999", ".", "9,5", "1.2.3", "-"};
  const std::vector<std::string> corners{"1", "2", "3", "4", "5", "-1", "-2", "2/3", "1//2", "3/1/2", "+3", "0004"};
  const std::vector<std::string> bad_corners{"0", "9", "x", "-9", "12345678901", "-", "1/x"};
  const std::vector<std::string> separators{" ", " ", " ", " ", " ", "  ", "\t", " \r", ""};
  const std::vector<std::string> others{"vt 0 1", "vn 0 0 1", "# note", "g part", "o thing", "s 1", "usemtl m",
                                        "", "   ", "vp 1", "l 1 2", "bogus"};
  const auto token = [&](const std::vector<std::string>& good, const std::vector<std::string>& bad) {
    return rng() % 10 == 0 ? pick(bad) : pick(good);
  };
  std::size_t taken = 0;
  const int files = 600;
  for (int k = 0; k < files; ++k) {
    std::string text = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 1\n";
    const int lines = 2 + static_cast<int>(rng() % 10);
    for (int l = 0; l < lines; ++l) {
      const auto kind = rng() % 20;
      if (kind < 9) {
        text += "v";
        for (int t = 0, n = 2 + static_cast<int>(rng() % 3); t < n; ++t) {
          text += (t == 0 ? " " : pick(separators)) + token(numbers, bad_numbers);
        }
      } else if (kind < 17) {
        text += "f";
        for (int t = 0, n = static_cast<int>(rng() % 6); t < n; ++t) {
          text += (t == 0 ? " " : pick(separators)) + token(corners, bad_corners);
        }
      } else {
        text += rng() % 4 == 0 ? pick(others) : "vt 0.5 0.5";
      }
      text += rng() % 8 == 0 ? "\r\n" : "\n";
    }
    SCOPED_TRACE(text);
    taken += check(dir, text) ? 1 : 0;
    if (::testing::Test::HasFailure()) break;
  }
  EXPECT_GT(taken, 20u) << "the alphabet should let the fast path take some files";
}

}  // namespace
}  // namespace exao
