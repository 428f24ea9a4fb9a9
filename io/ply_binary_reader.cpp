#include "io/ply_binary_reader.h"

#include "io/ply_header.h"

#include <bit>
#include <cstdint>
#include <cstring>
#include <sstream>
#include <string>
#include <vector>

#include <glm/glm.hpp>

namespace exao {
namespace {

using ply::Type;
using ply::size_of;
using ply::is_integer;

template <class T>
T load(const unsigned char* p, bool swap) {
  T v;
  if (!swap) {
    std::memcpy(&v, p, sizeof(T));
    return v;
  }
  unsigned char b[sizeof(T)];
  for (std::size_t i = 0; i < sizeof(T); ++i) b[i] = p[sizeof(T) - 1 - i];
  std::memcpy(&v, b, sizeof(T));
  return v;
}

// A value of an integer or floating type, as CGAL's reader turns it into its own: a double for
// coordinates, an integer for counts and indices.
double as_double(const unsigned char* p, Type t, bool swap) {
  switch (t) {
    case Type::I8: return static_cast<std::int8_t>(p[0]);
    case Type::U8: return p[0];
    case Type::I16: return load<std::int16_t>(p, swap);
    case Type::U16: return load<std::uint16_t>(p, swap);
    case Type::I32: return load<std::int32_t>(p, swap);
    case Type::U32: return load<std::uint32_t>(p, swap);
    case Type::F32: return load<float>(p, swap);
    case Type::F64: return load<double>(p, swap);
    case Type::None: return 0.0;
  }
  return 0.0;
}

std::int64_t as_integer(const unsigned char* p, Type t, bool swap) {
  switch (t) {
    case Type::I8: return static_cast<std::int8_t>(p[0]);
    case Type::U8: return p[0];
    case Type::I16: return load<std::int16_t>(p, swap);
    case Type::U16: return load<std::uint16_t>(p, swap);
    case Type::I32: return load<std::int32_t>(p, swap);
    case Type::U32: return load<std::uint32_t>(p, swap);
    default: return 0;
  }
}

constexpr std::uint64_t kProgressStep = 1 << 16;  // faces between progress reports

}  // namespace

std::optional<Result<Scene>> read_binary_ply(std::string_view file, const ProgressCallback& progress) {
  const std::optional<ply::Header> header = ply::read_header(file);
  if (!header) return std::nullopt;
  const std::string& format = header->format;
  const std::vector<ply::Element>& elements = header->elements;
  std::size_t pos = header->data;
  if (format != "binary_little_endian" && format != "binary_big_endian") return std::nullopt;
  const bool swap = (format == "binary_big_endian") != (std::endian::native == std::endian::big);

  // The layouts taken: "vertex" of scalars with x, y, z; then "face" with one integer list
  // "vertex_indices" (or "vertex_index") and scalars. Other elements only of scalars.
  const ply::Element* vertex = nullptr;
  const ply::Element* face = nullptr;
  for (const ply::Element& e : elements) {
    if (e.name == "vertex") {
      if (vertex || face || e.has_list) return std::nullopt;
      vertex = &e;
    } else if (e.name == "face") {
      if (face || !vertex) return std::nullopt;
      face = &e;
    } else if (e.has_list) {
      return std::nullopt;
    }
  }
  if (!vertex || !face || vertex->count == 0 || face->count == 0) return std::nullopt;
  std::size_t offset[3] = {0, 0, 0};
  Type coordinate[3] = {Type::None, Type::None, Type::None};
  for (std::size_t at = 0; const ply::Property& p : vertex->properties) {
    for (int k = 0; k < 3; ++k) {
      if (p.name == std::string(1, static_cast<char>('x' + k))) offset[k] = at, coordinate[k] = p.type;
    }
    at += size_of(p.type);
  }
  for (const Type t : coordinate) {
    if (t != Type::F32 && t != Type::F64) return std::nullopt;
  }
  int index_property = -1;
  for (std::size_t i = 0; i < face->properties.size(); ++i) {
    const ply::Property& p = face->properties[i];
    if (p.count_type == Type::None) continue;
    if (index_property >= 0 || (p.name != "vertex_indices" && p.name != "vertex_index") || !is_integer(p.type)) {
      return std::nullopt;
    }
    index_property = static_cast<int>(i);
  }
  if (index_property < 0) return std::nullopt;

  const auto* bytes = reinterpret_cast<const unsigned char*>(file.data());
  const std::size_t size = file.size();
  const auto truncated = [](const std::string& where) { return Result<Scene>(fail("the data ends inside " + where)); };
  std::vector<glm::vec3> points;
  for (const ply::Element& e : elements) {
    if (&e == face) break;
    if (&e != vertex) {
      if (e.count > (size - pos) / std::max<std::size_t>(1, e.scalar_bytes)) return truncated("element '" + e.name + "'");
      pos += e.count * e.scalar_bytes;
      continue;
    }
    if (e.scalar_bytes == 0 || e.count > (size - pos) / e.scalar_bytes) return truncated("element 'vertex'");
    points.resize(e.count);
    for (std::uint64_t v = 0; v < e.count; ++v, pos += e.scalar_bytes) {
      const unsigned char* p = bytes + pos;
      // CGAL reads a double, then exao rounds it to float: the same floats either way.
      points[v] = glm::vec3(static_cast<float>(as_double(p + offset[0], coordinate[0], swap)),
                            static_cast<float>(as_double(p + offset[1], coordinate[1], swap)),
                            static_cast<float>(as_double(p + offset[2], coordinate[2], swap)));
    }
  }

  Scene scene;
  scene.vertices.reserve(3 * face->count + Scene::kVertexPadding);
  scene.two_sided.reserve(face->count);
  scene.material.reserve(face->count);
  const std::size_t count_size = size_of(face->properties[static_cast<std::size_t>(index_property)].count_type);
  const Type count_type = face->properties[static_cast<std::size_t>(index_property)].count_type;
  const Type index_type = face->properties[static_cast<std::size_t>(index_property)].type;
  const std::size_t index_size = size_of(index_type);
  std::size_t before = 0, after = 0;  // scalar bytes before and after the list
  for (std::size_t i = 0; i < face->properties.size(); ++i) {
    if (static_cast<int>(i) == index_property) continue;
    (static_cast<int>(i) < index_property ? before : after) += size_of(face->properties[i].type);
  }
  std::size_t too_small = 0;
  std::vector<std::size_t> polygon;
  for (std::uint64_t f = 0; f < face->count; ++f) {
    if (size - pos < before + count_size) return truncated("element 'face' entry " + std::to_string(f));
    pos += before;
    const std::int64_t n = as_integer(bytes + pos, count_type, swap);
    pos += count_size;
    if (n < 0 || static_cast<std::uint64_t>(n) > (size - pos) / index_size) {
      return Result<Scene>(fail("element 'face' entry " + std::to_string(f) + ": a list of " + std::to_string(n) +
                                " items does not fit in the " + std::to_string(size - pos) + " bytes left"));
    }
    polygon.resize(static_cast<std::size_t>(n));
    for (std::int64_t k = 0; k < n; ++k, pos += index_size) {
      // As CGAL stores it: the index converted to size_t (a negative one wraps, and is refused).
      const auto v = static_cast<std::size_t>(as_integer(bytes + pos, index_type, swap));
      if (v >= points.size()) {
        return Result<Scene>(fail("face " + std::to_string(f + 1) + " refers to vertex " +
                                  std::to_string(static_cast<long long>(v)) + ", file has " + std::to_string(points.size())));
      }
      polygon[static_cast<std::size_t>(k)] = v;
    }
    if (size - pos < after) return truncated("element 'face' entry " + std::to_string(f));
    pos += after;
    if (polygon.size() < 3) {
      ++too_small;
      continue;
    }
    // Fan from the first corner, as the CGAL path does.
    for (std::size_t k = 1; k + 1 < polygon.size(); ++k) {
      scene.add_triangle(points[polygon[0]], points[polygon[k]], points[polygon[k + 1]], true, -1);
    }
    if (progress && (f + 1) % kProgressStep == 0) progress(pos, size);
  }
  if (progress) progress(size, size);
  if (too_small > 0) scene.report.notes.push_back(std::to_string(too_small) + " faces with fewer than 3 vertices skipped");
  if (scene.triangle_count() == 0) return Result<Scene>(fail("no triangles"));
  return Result<Scene>(std::move(scene));
}

}  // namespace exao
