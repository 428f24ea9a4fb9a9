#include "io/stl_binary_reader.h"

#include <algorithm>
#include <bit>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>

#include <glm/glm.hpp>

namespace exao {
namespace {

constexpr std::size_t kHeader = 80;      // free text, then a uint32 facet count
constexpr std::size_t kRecord = 50;      // normal, three corners (12 floats), 2 attribute bytes
constexpr std::size_t kProgressStep = 1 << 16;  // facets between progress reports

// Whether CGAL 5.5's read_STL (CGAL/IO/STL.h) tries ASCII first: after leading white space the
// word "solid" and a space or line end. Such a file is binary for it only when the ASCII parse
// fails with nothing read, which needs no "facet" token (the only place it stores a vertex) and
// no "endsolid" (its only way to succeed); a substring search is a conservative test of both.
bool cgal_may_read_as_ascii(std::string_view file) {
  std::size_t first = 0;
  while (first < file.size() && std::isspace(static_cast<unsigned char>(file[first]))) ++first;
  const std::string_view rest = file.substr(first);
  if (rest.size() < 6 || rest.substr(0, 5) != "solid") return false;
  if (rest[5] != '\n' && rest[5] != '\r' && rest[5] != ' ') return false;
  return file.find("facet") != std::string_view::npos || file.find("endsolid") != std::string_view::npos;
}

float little_endian_float(const unsigned char* p) {
  std::uint32_t bits = 0;
  for (int i = 3; i >= 0; --i) bits = bits << 8 | p[i];
  return std::bit_cast<float>(bits);
}

}  // namespace

std::optional<Result<Scene>> read_binary_stl(std::string_view file, const ProgressCallback& progress) {
  if (file.size() < kHeader + 4 || cgal_may_read_as_ascii(file)) return std::nullopt;
  const auto* bytes = reinterpret_cast<const unsigned char*>(file.data());
  const std::uint64_t count = std::uint64_t{bytes[kHeader]} | std::uint64_t{bytes[kHeader + 1]} << 8 |
                              std::uint64_t{bytes[kHeader + 2]} << 16 | std::uint64_t{bytes[kHeader + 3]} << 24;
  // CGAL reads the stated count and ignores what follows; a shorter file fails its binary read.
  if (count == 0 || count > (file.size() - kHeader - 4) / kRecord) return std::nullopt;

  Scene scene;
  scene.reserve(count);
  const unsigned char* record = bytes + kHeader + 4;
  for (std::uint64_t f = 0; f < count; ++f, record += kRecord) {
    glm::vec3 corner[3];
    for (int k = 0; k < 3; ++k) {
      for (int c = 0; c < 3; ++c) {
        const float x = little_endian_float(record + 12 * (k + 1) + 4 * c);
        // CGAL's map takes -0 for +0 and a NaN for its neighbours: it would hand back another
        // vertex's float.
        if (std::isnan(x) || (x == 0.0f && std::signbit(x))) return std::nullopt;
        corner[k][c] = x;
      }
    }
    scene.add_triangle(corner[0], corner[1], corner[2], true, -1);
    if (progress && (f + 1) % kProgressStep == 0) progress(kHeader + 4 + (f + 1) * kRecord, file.size());
  }
  if (progress) progress(file.size(), file.size());
  if (scene.triangle_count() == 0) return Result<Scene>(fail("no triangles"));
  return Result<Scene>(std::move(scene));
}

}  // namespace exao
