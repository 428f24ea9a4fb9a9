#include "io/obj_ascii_reader.h"
#include "io/obj_ignored_statements.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "io/stream_cursor.h"

namespace exao {
namespace {


constexpr std::size_t kProgressStep = std::size_t{1} << 22;  // bytes between progress reports

}  // namespace

std::optional<Result<Scene>> read_ascii_obj(std::string_view file, const ProgressCallback& progress) {
  std::vector<glm::vec3> points;  // as the CGAL path rounds them: the double read, to float
  Scene scene;
  // Sized from the file: a terrain's OBJ has about 25 bytes a triangle.
  points.reserve(file.size() / 64);
  const std::size_t guess = file.size() / 24;
  scene.reserve(guess);

  std::vector<std::size_t> polygon;
  std::size_t faces = 0;
  std::size_t too_small = 0;
  std::size_t next_report = kProgressStep;
  const char* const begin = file.data();
  const char* const stop = begin + file.size();
  for (const char* line = begin; line != stop;) {
    // getline: a line ends at '\n', and the last one may have none.
    const char* eol = static_cast<const char*>(std::memchr(line, '\n', static_cast<std::size_t>(stop - line)));
    if (eol == nullptr) eol = stop;
    StreamCursor in{line, eol};
    line = eol == stop ? stop : eol + 1;
    const std::string_view keyword = in.word();
    if (keyword.empty()) continue;
    if (keyword == "v") {
      double x = 0.0, y = 0.0, z = 0.0;
      if (!in.number(x) || !in.number(y) || !in.number(z)) return std::nullopt;
      points.emplace_back(static_cast<float>(x), static_cast<float>(y), static_cast<float>(z));
    } else if (keyword == "f") {
      ++faces;
      polygon.clear();
      long long i = 0;
      while (in.integer(i)) {
        // CGAL: a positive index counts from 1, zero and negative ones back from the vertices
        // read so far. Anything but a vertex already read goes to CGAL (forward references, or
        // the error it reports).
        const long long v = i < 1 ? static_cast<long long>(points.size()) + i : i - 1;
        if (v < 0 || static_cast<std::size_t>(v) >= points.size()) return std::nullopt;
        polygon.push_back(static_cast<std::size_t>(v));
        in.ignore_through_space();
      }
      if (polygon.size() < 3) {
        ++too_small;
        continue;
      }
      // Fan from the first corner, as the CGAL path does.
      for (std::size_t k = 1; k + 1 < polygon.size(); ++k) {
        scene.add_triangle(points[polygon[0]], points[polygon[k]], points[polygon[k + 1]], true, -1);
      }
    } else if (keyword.front() != '#' &&
               std::find(kObjIgnoredStatements.begin(), kObjIgnoredStatements.end(), keyword) ==
                   kObjIgnoredStatements.end()) {
      return std::nullopt;  // CGAL refuses the file: its path says why
    }
    if (progress && static_cast<std::size_t>(line - begin) >= next_report) {
      progress(static_cast<std::size_t>(line - begin), file.size());
      next_report += kProgressStep;
    }
  }
  if (points.empty() || faces == 0) return std::nullopt;
  if (progress) progress(file.size(), file.size());
  if (too_small > 0) scene.report.notes.push_back(std::to_string(too_small) + " faces with fewer than 3 vertices skipped");
  if (scene.triangle_count() == 0) return Result<Scene>(fail("no triangles"));
  return Result<Scene>(std::move(scene));
}

}  // namespace exao
