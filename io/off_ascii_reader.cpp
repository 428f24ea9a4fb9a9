#include "io/off_ascii_reader.h"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "io/stream_cursor.h"

namespace exao {
namespace {

constexpr std::uint64_t kProgressStep = 1 << 16;  // faces between progress reports
// Below 2^53 a double holds every integer, and CGAL's cast to size_t truncates it.
constexpr double kMaxExactInteger = 9007199254740992.0;

// CGAL's next line, as skip_comment_OFF and std::getline give it: white space and '#' comment
// lines skipped, then up to the '\n' (which `ended` says was there), cut at a '#'.
struct LineReader {
  const char* p;
  const char* end;

  bool next(StreamCursor& line, bool& ended) {
    for (;;) {
      while (p != end && is_stream_space(*p)) ++p;
      if (p == end) return false;
      if (*p != '#') break;
      while (p != end && *p != '\n') ++p;
    }
    const char* start = p;
    const char* eol = static_cast<const char*>(std::memchr(p, '\n', static_cast<std::size_t>(end - p)));
    ended = eol != nullptr;
    if (eol == nullptr) eol = end;
    p = eol == end ? end : eol + 1;
    const char* hash = static_cast<const char*>(std::memchr(start, '#', static_cast<std::size_t>(eol - start)));
    line = StreamCursor{start, hash != nullptr ? hash : eol};
    return true;
  }
};

// A face's size or index: CGAL reads a double and casts it to size_t (an index of 2.5 is 2).
// A size must be a whole number: the pre-scan measures a line by the double (3.5 corners on a
// line of 3 indices is its error).
bool whole(StreamCursor& line, std::size_t& out, bool integral) {
  double d = 0.0;
  if (!line.number(d) || !(d >= 0.0 && d < kMaxExactInteger) || (integral && d != std::floor(d))) return false;
  out = static_cast<std::size_t>(d);
  return true;
}

}  // namespace

std::optional<Result<Scene>> read_ascii_off(std::string_view file, const ProgressCallback& progress) {
  // The header (File_header_OFF's operator>>): "OFF", one character after it, then the vertex
  // count (which must start with a digit) and the face and edge counts as `>> int` reads them.
  StreamCursor in{file.data(), file.data() + file.size()};
  in.skip_space();
  if (in.end - in.p < 4 || std::string_view(in.p, 3) != "OFF" || !is_stream_space(in.p[3])) return std::nullopt;
  in.p += 4;
  in.skip_space();
  if (in.p != in.end && *in.p == '#') return std::nullopt;
  std::uint64_t vertices = 0;
  long long faces = 0, edges = 0;
  if (!in.digits(vertices, std::numeric_limits<int>::max()) || !in.integer(faces) || !in.integer(edges)) return std::nullopt;
  if (vertices == 0 || faces <= 0 || vertices > file.size() || static_cast<std::uint64_t>(faces) > file.size()) {
    return std::nullopt;
  }

  LineReader lines{in.p, in.end};
  StreamCursor line{nullptr, nullptr};
  bool ended = false;
  // CGAL's point is x / w with w = 1 (exact); exao rounds the double to float.
  std::vector<glm::vec3> points(vertices);
  for (glm::vec3& point : points) {
    double x = 0.0, y = 0.0, z = 0.0;
    // A vertex line that ends the file leaves CGAL's stream at its end: the read fails.
    if (!lines.next(line, ended) || !ended || !line.number(x) || !line.number(y) || !line.number(z)) return std::nullopt;
    point = glm::vec3(static_cast<float>(x), static_cast<float>(y), static_cast<float>(z));
  }

  Scene scene;
  const auto face_count = static_cast<std::size_t>(faces);
  scene.reserve(face_count);
  std::vector<std::size_t> polygon;
  std::size_t too_small = 0;
  for (std::size_t f = 0; f < face_count; ++f) {
    std::size_t n = 0;
    if (!lines.next(line, ended) || !whole(line, n, true)) return std::nullopt;
    polygon.clear();
    for (std::size_t k = 0; k < n; ++k) {
      std::size_t v = 0;
      if (!whole(line, v, false) || v >= points.size()) return std::nullopt;
      polygon.push_back(v);
    }
    if (polygon.size() < 3) {
      ++too_small;
      continue;
    }
    // Fan from the first corner, as the CGAL path does.
    for (std::size_t k = 1; k + 1 < polygon.size(); ++k) {
      scene.add_triangle(points[polygon[0]], points[polygon[k]], points[polygon[k + 1]], true, -1);
    }
    if (progress && (f + 1) % kProgressStep == 0) progress(static_cast<std::size_t>(lines.p - file.data()), file.size());
  }
  if (progress) progress(file.size(), file.size());
  if (too_small > 0) scene.report.notes.push_back(std::to_string(too_small) + " faces with fewer than 3 vertices skipped");
  if (scene.triangle_count() == 0) return Result<Scene>(fail("no triangles"));
  return Result<Scene>(std::move(scene));
}

}  // namespace exao
