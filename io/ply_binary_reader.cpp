#include "io/ply_binary_reader.h"

#include "io/ply_header.h"

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstring>
#include <optional>
#include <sstream>
#include <string>
#include <type_traits>
#include <vector>

#include <glm/glm.hpp>

#include "core/huge_pages.h"

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
// coordinates (Number double), an integer for counts and indices (Number std::int64_t, for
// which a floating type reads as 0).
template <class Number>
Number as_number(const unsigned char* p, Type t, bool swap) {
  switch (t) {
    case Type::I8: return static_cast<std::int8_t>(p[0]);
    case Type::U8: return p[0];
    case Type::I16: return load<std::int16_t>(p, swap);
    case Type::U16: return load<std::uint16_t>(p, swap);
    case Type::I32: return load<std::int32_t>(p, swap);
    case Type::U32: return load<std::uint32_t>(p, swap);
    case Type::F32:
      if constexpr (std::is_floating_point_v<Number>) return load<float>(p, swap);
      return 0;
    case Type::F64:
      if constexpr (std::is_floating_point_v<Number>) return load<double>(p, swap);
      return 0;
    case Type::None: return 0;
  }
  return 0;
}

constexpr std::uint64_t kProgressStep = 1 << 16;  // faces between progress reports

// What the fast path reads, found in the header: the "vertex" and "face" elements, where x, y, z
// lie in a vertex entry and their types, and which of the face's properties is its index list.
struct Layout {
  const ply::Element* vertex = nullptr;
  const ply::Element* face = nullptr;
  std::size_t offset[3] = {0, 0, 0};
  Type coordinate[3] = {Type::None, Type::None, Type::None};
  std::size_t index_property = 0;
};

// The layouts taken: "vertex" of scalars; then "face"; other elements only of scalars. Both must
// have entries. False for any other layout.
bool find_vertex_and_face(const std::vector<ply::Element>& elements, Layout& layout) {
  for (const ply::Element& e : elements) {
    if (e.name == "vertex") {
      if (layout.vertex || layout.face || e.has_list) return false;
      layout.vertex = &e;
    } else if (e.name == "face") {
      if (layout.face || !layout.vertex) return false;
      layout.face = &e;
    } else if (e.has_list) {
      return false;
    }
  }
  return layout.vertex && layout.face && layout.vertex->count != 0 && layout.face->count != 0;
}

// x, y, z in a vertex entry (the last property of each name wins); false unless all three are
// float or double.
bool find_coordinates(const ply::Element& vertex, Layout& layout) {
  for (std::size_t at = 0; const ply::Property& p : vertex.properties) {
    for (int k = 0; k < 3; ++k) {
      if (p.name == std::string(1, static_cast<char>('x' + k))) layout.offset[k] = at, layout.coordinate[k] = p.type;
    }
    at += size_of(p.type);
  }
  for (const Type t : layout.coordinate) {
    if (t != Type::F32 && t != Type::F64) return false;
  }
  return true;
}

// The face's one list, "vertex_indices" (or "vertex_index") of integers, among scalars; nullopt
// for no list, a second list, or a list of another name or item type.
std::optional<std::size_t> index_list_of(const ply::Element& face) {
  std::optional<std::size_t> found;
  for (std::size_t i = 0; i < face.properties.size(); ++i) {
    const ply::Property& p = face.properties[i];
    if (p.count_type == Type::None) continue;
    if (found || (p.name != "vertex_indices" && p.name != "vertex_index") || !is_integer(p.type)) {
      return std::nullopt;
    }
    found = i;
  }
  return found;
}

std::optional<Layout> layout_of(const std::vector<ply::Element>& elements) {
  Layout layout;
  if (!find_vertex_and_face(elements, layout) || !find_coordinates(*layout.vertex, layout)) return std::nullopt;
  const std::optional<std::size_t> list = index_list_of(*layout.face);
  if (!list) return std::nullopt;
  layout.index_property = *list;
  return layout;
}

// The data section as the reader walks it; every read checks what is left first.
struct Cursor {
  const unsigned char* bytes = nullptr;
  std::size_t size = 0;
  std::size_t pos = 0;
  bool swap = false;
  [[nodiscard]] std::size_t left() const { return size - pos; }
};

std::unexpected<Error> truncated(const std::string& where) { return fail("the data ends inside " + where); }

// The entries of element `vertex` into `points` (sized). `Floats`: the common layout, float
// coordinates in the machine's byte order, read without the per-value switch on the type.
template <bool Floats>
void read_vertices(const ply::Element& vertex, const Layout& layout, Cursor& in, std::vector<glm::vec3>& points) {
  for (std::uint64_t v = 0; v < vertex.count; ++v, in.pos += vertex.scalar_bytes) {
    const unsigned char* p = in.bytes + in.pos;
    const auto coordinate = [&](int k) {
      if constexpr (Floats) {
        return static_cast<double>(load<float>(p + layout.offset[k], false));
      } else {
        return as_number<double>(p + layout.offset[k], layout.coordinate[k], in.swap);
      }
    };
    // CGAL reads a double, then exao rounds it to float: the same floats either way.
    points[v] = glm::vec3(static_cast<float>(coordinate(0)), static_cast<float>(coordinate(1)), static_cast<float>(coordinate(2)));
  }
}

// The vertex positions; the scalar elements before "face" other than "vertex" skipped by size.
Result<std::vector<glm::vec3>> read_points(const std::vector<ply::Element>& elements, const Layout& layout, Cursor& in) {
  std::vector<glm::vec3> points;
  for (const ply::Element& e : elements) {
    if (&e == layout.face) break;
    if (&e != layout.vertex) {
      if (e.count > in.left() / std::max<std::size_t>(1, e.scalar_bytes)) return truncated("element '" + e.name + "'");
      in.pos += e.count * e.scalar_bytes;
      continue;
    }
    if (e.scalar_bytes == 0 || e.count > in.left() / e.scalar_bytes) return truncated("element 'vertex'");
    reserve_huge(points, e.count);
    points.resize(e.count);
    if (!in.swap && std::all_of(layout.coordinate, layout.coordinate + 3, [](Type t) { return t == Type::F32; })) {
      read_vertices<true>(e, layout, in, points);
    } else {
      read_vertices<false>(e, layout, in, points);
    }
  }
  return points;
}

// A face entry's bytes: scalars before the index list, its count and item types, scalars after.
struct FaceEntry {
  Type count_type = Type::None;
  std::size_t count_size = 0;
  Type index_type = Type::None;
  std::size_t index_size = 0;
  std::size_t before = 0, after = 0;
};

FaceEntry face_entry_of(const ply::Element& face, std::size_t index_property) {
  FaceEntry entry;
  entry.count_type = face.properties[index_property].count_type;
  entry.count_size = size_of(entry.count_type);
  entry.index_type = face.properties[index_property].type;
  entry.index_size = size_of(entry.index_type);
  for (std::size_t i = 0; i < face.properties.size(); ++i) {
    if (i == index_property) continue;
    (i < index_property ? entry.before : entry.after) += size_of(face.properties[i].type);
  }
  return entry;
}

// Face entry `f` (from 0) into `polygon`, each index checked against the `vertex_count` vertices.
// `Index`: the index type when the entry is the common one (a uchar count, 32-bit indices,
// nothing else, in the machine's order), read without the per-value switch; void otherwise.
template <class Index = void>
Result<void> read_polygon(Cursor& in, const FaceEntry& entry, std::uint64_t f, std::size_t vertex_count,
                          std::vector<std::size_t>& polygon) {
  constexpr bool kCommon = !std::is_void_v<Index>;
  if (in.left() < entry.before + entry.count_size) return truncated("element 'face' entry " + std::to_string(f));
  in.pos += entry.before;
  const std::int64_t n = kCommon ? std::int64_t{in.bytes[in.pos]} : as_number<std::int64_t>(in.bytes + in.pos, entry.count_type, in.swap);
  in.pos += entry.count_size;
  if (n < 0 || static_cast<std::uint64_t>(n) > in.left() / entry.index_size) {
    return fail("element 'face' entry " + std::to_string(f) + ": a list of " + std::to_string(n) +
                " items does not fit in the " + std::to_string(in.left()) + " bytes left");
  }
  polygon.resize(static_cast<std::size_t>(n));
  for (std::int64_t k = 0; k < n; ++k, in.pos += entry.index_size) {
    // As CGAL stores it: the index converted to size_t (a negative one wraps, and is refused).
    std::int64_t index = 0;
    if constexpr (kCommon) {
      index = load<Index>(in.bytes + in.pos, false);
    } else {
      index = as_number<std::int64_t>(in.bytes + in.pos, entry.index_type, in.swap);
    }
    const auto v = static_cast<std::size_t>(index);
    if (v >= vertex_count) {
      return fail("face " + std::to_string(f + 1) + " refers to vertex " + std::to_string(static_cast<long long>(v)) +
                  ", file has " + std::to_string(vertex_count));
    }
    polygon[static_cast<std::size_t>(k)] = v;
  }
  if (in.left() < entry.after) return truncated("element 'face' entry " + std::to_string(f));
  in.pos += entry.after;
  return {};
}

// The faces as two-sided triangles; faces of fewer than 3 corners skipped and counted in a note.
template <class Index>
Result<Scene> read_faces(const ply::Element& face, const FaceEntry& entry, const std::vector<glm::vec3>& points,
                         Cursor& in, const ProgressCallback& progress) {
  Scene scene;
  scene.reserve(face.count);
  std::size_t too_small = 0;
  std::vector<std::size_t> polygon;
  for (std::uint64_t f = 0; f < face.count; ++f) {
    if (Result<void> read = read_polygon<Index>(in, entry, f, points.size(), polygon); !read) {
      return std::unexpected(std::move(read.error()));
    }
    if (polygon.size() < 3) {
      ++too_small;
      continue;
    }
    // Fan from the first corner, as the CGAL path does.
    for (std::size_t k = 1; k + 1 < polygon.size(); ++k) {
      scene.add_triangle(points[polygon[0]], points[polygon[k]], points[polygon[k + 1]], true, -1);
    }
    if (progress && (f + 1) % kProgressStep == 0) progress(in.pos, in.size);
  }
  if (progress) progress(in.size, in.size);
  if (too_small > 0) scene.report.notes.push_back(std::to_string(too_small) + " faces with fewer than 3 vertices skipped");
  if (scene.triangle_count() == 0) return fail("no triangles");
  return scene;
}

}  // namespace

std::optional<Result<Scene>> read_binary_ply(std::string_view file, const ProgressCallback& progress) {
  const std::optional<ply::Header> header = ply::read_header(file);
  if (!header) return std::nullopt;
  const std::string& format = header->format;
  if (format != "binary_little_endian" && format != "binary_big_endian") return std::nullopt;
  const bool swap = (format == "binary_big_endian") != (std::endian::native == std::endian::big);
  const std::optional<Layout> layout = layout_of(header->elements);
  if (!layout) return std::nullopt;

  Cursor in{reinterpret_cast<const unsigned char*>(file.data()), file.size(), header->data, swap};
  const Result<std::vector<glm::vec3>> points = read_points(header->elements, *layout, in);
  if (!points) return Result<Scene>(std::unexpected(points.error()));
  const FaceEntry entry = face_entry_of(*layout->face, layout->index_property);
  if (!swap && entry.before == 0 && entry.after == 0 && entry.count_type == Type::U8) {
    if (entry.index_type == Type::I32) return read_faces<std::int32_t>(*layout->face, entry, *points, in, progress);
    if (entry.index_type == Type::U32) return read_faces<std::uint32_t>(*layout->face, entry, *points, in, progress);
  }
  return read_faces<void>(*layout->face, entry, *points, in, progress);
}

}  // namespace exao
