#include "io/ply_ascii_reader.h"

#include <algorithm>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "io/ply_header.h"
#include "io/stream_cursor.h"

namespace exao {
namespace {

using ply::Type;

constexpr std::uint64_t kProgressStep = 1 << 16;  // faces between progress reports

// The largest value of an integer type: plain digits up to it are read alike by CGAL's stream
// (char types go through short and unsigned short, PLY_read_number::read_ascii, then are cast)
// and keep their value in the type.
std::uint64_t largest(Type t) {
  switch (t) {
    case Type::I8: return std::numeric_limits<std::int8_t>::max();
    case Type::U8: return std::numeric_limits<std::uint8_t>::max();
    case Type::I16: return std::numeric_limits<std::int16_t>::max();
    case Type::U16: return std::numeric_limits<std::uint16_t>::max();
    case Type::I32: return std::numeric_limits<std::int32_t>::max();
    case Type::U32: return std::numeric_limits<std::uint32_t>::max();
    default: return 0;
  }
}

// One scalar of type `t` as CGAL reads it, as a double (the point reader widens float to double);
// false where the fast path does not follow the stream.
bool scalar(StreamCursor& in, Type t, double& out) {
  if (t == Type::F32) {
    float f = 0.0f;
    if (!in.number(f)) return false;
    out = f;
    return true;
  }
  if (t == Type::F64) return in.number(out);
  std::uint64_t v = 0;
  if (!in.digits(v, largest(t))) return false;
  out = static_cast<double>(v);
  return true;
}

}  // namespace

std::optional<Result<Scene>> read_ascii_ply(std::string_view file, const ProgressCallback& progress) {
  const std::optional<ply::Header> header = ply::read_header(file);
  if (!header || header->format != "ascii" || header->elements.size() != 2) return std::nullopt;
  const ply::Element& vertex = header->elements[0];
  const ply::Element& face = header->elements[1];
  if (vertex.name != "vertex" || face.name != "face" || vertex.has_list || vertex.count == 0 || face.count == 0) {
    return std::nullopt;
  }
  // Where x, y and z are among the vertex's scalars (the first of each name, as CGAL looks them up).
  int axis[3] = {-1, -1, -1};
  for (std::size_t i = 0; i < vertex.properties.size(); ++i) {
    const ply::Property& p = vertex.properties[i];
    for (int k = 0; k < 3; ++k) {
      if (axis[k] < 0 && p.name == std::string(1, static_cast<char>('x' + k))) {
        if (p.type != Type::F32 && p.type != Type::F64) return std::nullopt;
        axis[k] = static_cast<int>(i);
      }
    }
  }
  if (axis[0] < 0 || axis[1] < 0 || axis[2] < 0) return std::nullopt;
  if (face.properties.size() != 1) return std::nullopt;
  const ply::Property& list = face.properties[0];
  if (list.count_type == Type::None || (list.type != Type::I32 && list.type != Type::U32) ||
      (list.name != "vertex_indices" && list.name != "vertex_index")) {
    return std::nullopt;
  }

  StreamCursor in{file.data() + header->data, file.data() + file.size()};
  // CGAL's reader keeps a double per coordinate; exao rounds it to float.
  std::vector<glm::vec3> points(vertex.count);
  for (glm::vec3& point : points) {
    double xyz[3] = {0.0, 0.0, 0.0};
    for (std::size_t i = 0; i < vertex.properties.size(); ++i) {
      double value = 0.0;
      if (!scalar(in, vertex.properties[i].type, value)) return std::nullopt;
      for (int k = 0; k < 3; ++k) {
        if (axis[k] == static_cast<int>(i)) xyz[k] = value;
      }
    }
    point = glm::vec3(static_cast<float>(xyz[0]), static_cast<float>(xyz[1]), static_cast<float>(xyz[2]));
  }

  Scene scene;
  scene.reserve(face.count);
  std::vector<std::size_t> polygon;
  std::size_t too_small = 0;
  // A list longer than the file could hold is the pre-scan's to refuse; this bound only keeps a
  // count from asking for more than the bytes left.
  const std::uint64_t max_count = std::min<std::uint64_t>(largest(list.count_type), file.size());
  for (std::uint64_t f = 0; f < face.count; ++f) {
    std::uint64_t n = 0;
    if (!in.digits(n, max_count)) return std::nullopt;
    polygon.resize(static_cast<std::size_t>(n));
    for (std::size_t& v : polygon) {
      std::uint64_t index = 0;
      if (!in.digits(index, std::numeric_limits<std::int32_t>::max()) || index >= points.size()) return std::nullopt;
      v = static_cast<std::size_t>(index);
    }
    if (polygon.size() < 3) {
      ++too_small;
      continue;
    }
    // Fan from the first corner, as the CGAL path does.
    for (std::size_t k = 1; k + 1 < polygon.size(); ++k) {
      scene.add_triangle(points[polygon[0]], points[polygon[k]], points[polygon[k + 1]], true, -1);
    }
    if (progress && (f + 1) % kProgressStep == 0) progress(static_cast<std::size_t>(in.p - file.data()), file.size());
  }
  if (progress) progress(file.size(), file.size());
  if (too_small > 0) scene.report.notes.push_back(std::to_string(too_small) + " faces with fewer than 3 vertices skipped");
  if (scene.triangle_count() == 0) return Result<Scene>(fail("no triangles"));
  return Result<Scene>(std::move(scene));
}

}  // namespace exao
