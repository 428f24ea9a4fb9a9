#include "io/ply_binary_reader.h"

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstring>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <glm/glm.hpp>

namespace exao {
namespace {

enum class Type { None, I8, U8, I16, U16, I32, U32, F32, F64 };

Type type_of(const std::string& name) {
  if (name == "char" || name == "int8") return Type::I8;
  if (name == "uchar" || name == "uint8") return Type::U8;
  if (name == "short" || name == "int16") return Type::I16;
  if (name == "ushort" || name == "uint16") return Type::U16;
  if (name == "int" || name == "int32") return Type::I32;
  if (name == "uint" || name == "uint32") return Type::U32;
  if (name == "float" || name == "float32") return Type::F32;
  if (name == "double" || name == "float64") return Type::F64;
  return Type::None;
}

std::size_t size_of(Type t) {
  switch (t) {
    case Type::I8: case Type::U8: return 1;
    case Type::I16: case Type::U16: return 2;
    case Type::I32: case Type::U32: case Type::F32: return 4;
    case Type::F64: return 8;
    case Type::None: return 0;
  }
  return 0;
}

struct Property {
  std::string name;
  Type type = Type::None;        // scalar, or a list's items
  Type count_type = Type::None;  // a list's count; None for a scalar
};

struct Element {
  std::string name;
  std::uint64_t count = 0;
  std::vector<Property> properties;
  std::size_t scalar_bytes = 0;  // when no property is a list: the bytes of one entry
  bool has_list = false;
};

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

bool is_integer(Type t) { return t != Type::None && t != Type::F32 && t != Type::F64; }

// The header, as the pre-scan reads it: the format, the elements and where the data starts.
struct Header {
  std::string format;
  std::vector<Element> elements;
  std::size_t data = 0;  // the byte after end_header's line
  bool swap = false;     // the data's byte order is not this machine's
};

// One "property" line into the last element; false for a layout this reader does not take.
bool read_property(std::istringstream& iss, std::vector<Element>& elements) {
  if (elements.empty()) return false;
  Property p;
  std::string type;
  iss >> type;
  if (type == "list") {
    std::string count_type, item_type;
    iss >> count_type >> item_type;
    p.count_type = type_of(count_type);
    p.type = type_of(item_type);
    if (!is_integer(p.count_type) || p.type == Type::None) return false;
    elements.back().has_list = true;
  } else {
    p.type = type_of(type);
    if (p.type == Type::None) return false;
    elements.back().scalar_bytes += size_of(p.type);
  }
  iss >> p.name;
  elements.back().properties.push_back(std::move(p));
  return true;
}

// nullopt for a file that is not binary PLY, or whose header this reader does not take.
std::optional<Header> read_header(std::string_view file) {
  Header h;
  std::size_t pos = 0;
  bool end_seen = false;
  for (int number = 1; number <= 10'000 && pos < file.size(); ++number) {
    const std::size_t eol = file.find('\n', pos);
    std::string line(file.substr(pos, eol == std::string_view::npos ? std::string_view::npos : eol - pos));
    pos = eol == std::string_view::npos ? file.size() : eol + 1;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::istringstream iss(line);
    std::string keyword;
    iss >> keyword;
    if (number == 1 && keyword != "ply") return std::nullopt;
    if (keyword == "format") {
      iss >> h.format;
    } else if (keyword == "element") {
      Element e;
      iss >> e.name >> e.count;
      if (!iss) return std::nullopt;
      h.elements.push_back(std::move(e));
    } else if (keyword == "property") {
      if (!read_property(iss, h.elements)) return std::nullopt;
    } else if (keyword == "end_header") {
      end_seen = true;
      break;
    }
  }
  if (!end_seen) return std::nullopt;
  if (h.format != "binary_little_endian" && h.format != "binary_big_endian") return std::nullopt;
  h.swap = (h.format == "binary_big_endian") != (std::endian::native == std::endian::big);
  h.data = pos;
  return h;
}

// The layouts taken: "vertex" of scalars with x, y, z; then "face" with one integer list
// "vertex_indices" (or "vertex_index") and scalars. Other elements only of scalars.
struct Layout {
  const Element* vertex = nullptr;
  const Element* face = nullptr;
  std::size_t offset[3] = {0, 0, 0};  // of x, y, z in a vertex entry
  Type coordinate[3] = {Type::None, Type::None, Type::None};
  std::size_t index_property = 0;     // the face's list
};

std::optional<Layout> choose_layout(const Header& h) {
  Layout l;
  for (const Element& e : h.elements) {
    if (e.name == "vertex") {
      if (l.vertex || l.face || e.has_list) return std::nullopt;
      l.vertex = &e;
    } else if (e.name == "face") {
      if (l.face || !l.vertex) return std::nullopt;
      l.face = &e;
    } else if (e.has_list) {
      return std::nullopt;
    }
  }
  if (!l.vertex || !l.face || l.vertex->count == 0 || l.face->count == 0) return std::nullopt;
  for (std::size_t at = 0; const Property& p : l.vertex->properties) {
    for (int k = 0; k < 3; ++k) {
      if (p.name == std::string(1, static_cast<char>('x' + k))) l.offset[k] = at, l.coordinate[k] = p.type;
    }
    at += size_of(p.type);
  }
  for (const Type t : l.coordinate) {
    if (t != Type::F32 && t != Type::F64) return std::nullopt;
  }
  int index_property = -1;
  for (std::size_t i = 0; i < l.face->properties.size(); ++i) {
    const Property& p = l.face->properties[i];
    if (p.count_type == Type::None) continue;
    if (index_property >= 0 || (p.name != "vertex_indices" && p.name != "vertex_index") || !is_integer(p.type)) {
      return std::nullopt;
    }
    index_property = static_cast<int>(i);
  }
  if (index_property < 0) return std::nullopt;
  l.index_property = static_cast<std::size_t>(index_property);
  return l;
}

Result<Scene> truncated(const std::string& where) { return fail("the data ends inside " + where); }

// The vertices, skipping the scalar elements before the faces; `pos` ends at the first face.
Result<std::vector<glm::vec3>> read_points(std::string_view file, const Header& h, const Layout& l, std::size_t& pos) {
  const auto* bytes = reinterpret_cast<const unsigned char*>(file.data());
  const std::size_t size = file.size();
  std::vector<glm::vec3> points;
  for (const Element& e : h.elements) {
    if (&e == l.face) break;
    if (&e != l.vertex) {
      if (e.count > (size - pos) / std::max<std::size_t>(1, e.scalar_bytes)) {
        return std::unexpected(truncated("element '" + e.name + "'").error());
      }
      pos += e.count * e.scalar_bytes;
      continue;
    }
    if (e.scalar_bytes == 0 || e.count > (size - pos) / e.scalar_bytes) return std::unexpected(truncated("element 'vertex'").error());
    points.resize(e.count);
    for (std::uint64_t v = 0; v < e.count; ++v, pos += e.scalar_bytes) {
      const unsigned char* p = bytes + pos;
      // CGAL reads a double, then exao rounds it to float: the same floats either way.
      points[v] = glm::vec3(static_cast<float>(as_double(p + l.offset[0], l.coordinate[0], h.swap)),
                            static_cast<float>(as_double(p + l.offset[1], l.coordinate[1], h.swap)),
                            static_cast<float>(as_double(p + l.offset[2], l.coordinate[2], h.swap)));
    }
  }
  return points;
}

// The faces from `pos` on, each fanned from its first corner into `scene`, as the CGAL path does.
Result<Scene> read_faces(std::string_view file, const Header& h, const Layout& l, std::size_t pos,
                         const std::vector<glm::vec3>& points, const ProgressCallback& progress) {
  const auto* bytes = reinterpret_cast<const unsigned char*>(file.data());
  const std::size_t size = file.size();
  const Element& face = *l.face;
  Scene scene;
  scene.vertices.reserve(3 * face.count + Scene::kVertexPadding);
  scene.two_sided.reserve(face.count);
  scene.material.reserve(face.count);
  const Property& list = face.properties[l.index_property];
  const std::size_t count_size = size_of(list.count_type);
  const std::size_t index_size = size_of(list.type);
  std::size_t before = 0, after = 0;  // scalar bytes before and after the list
  for (std::size_t i = 0; i < face.properties.size(); ++i) {
    if (i == l.index_property) continue;
    (i < l.index_property ? before : after) += size_of(face.properties[i].type);
  }
  std::size_t too_small = 0;
  std::vector<std::size_t> polygon;
  for (std::uint64_t f = 0; f < face.count; ++f) {
    if (size - pos < before + count_size) return truncated("element 'face' entry " + std::to_string(f));
    pos += before;
    const std::int64_t n = as_integer(bytes + pos, list.count_type, h.swap);
    pos += count_size;
    if (n < 0 || static_cast<std::uint64_t>(n) > (size - pos) / index_size) {
      return fail("element 'face' entry " + std::to_string(f) + ": a list of " + std::to_string(n) +
                  " items does not fit in the " + std::to_string(size - pos) + " bytes left");
    }
    polygon.resize(static_cast<std::size_t>(n));
    for (std::int64_t k = 0; k < n; ++k, pos += index_size) {
      // As CGAL stores it: the index converted to size_t (a negative one wraps, and is refused).
      const auto v = static_cast<std::size_t>(as_integer(bytes + pos, list.type, h.swap));
      if (v >= points.size()) {
        return fail("face " + std::to_string(f + 1) + " refers to vertex " + std::to_string(static_cast<long long>(v)) +
                    ", file has " + std::to_string(points.size()));
      }
      polygon[static_cast<std::size_t>(k)] = v;
    }
    if (size - pos < after) return truncated("element 'face' entry " + std::to_string(f));
    pos += after;
    if (polygon.size() < 3) {
      ++too_small;
      continue;
    }
    for (std::size_t k = 1; k + 1 < polygon.size(); ++k) {
      scene.add_triangle(points[polygon[0]], points[polygon[k]], points[polygon[k + 1]], true, -1);
    }
    if (progress && (f + 1) % kProgressStep == 0) progress(pos, size);
  }
  if (progress) progress(size, size);
  if (too_small > 0) scene.report.notes.push_back(std::to_string(too_small) + " faces with fewer than 3 vertices skipped");
  if (scene.triangle_count() == 0) return fail("no triangles");
  return scene;
}

}  // namespace

std::optional<Result<Scene>> read_binary_ply(std::string_view file, const ProgressCallback& progress) {
  const std::optional<Header> header = read_header(file);
  if (!header) return std::nullopt;
  const std::optional<Layout> layout = choose_layout(*header);
  if (!layout) return std::nullopt;
  std::size_t pos = header->data;
  Result<std::vector<glm::vec3>> points = read_points(file, *header, *layout, pos);
  if (!points) return Result<Scene>(std::unexpected(points.error()));
  return read_faces(file, *header, *layout, pos, *points, progress);
}

}  // namespace exao
