#pragma once
// A PLY file's header (its format, elements and properties, and where the data starts), read as
// io/soup_prescan.h's pre-scan and CGAL 5.5's reader read it: shared by the binary and the ASCII
// fast paths (io/ply_binary_reader.h, io/ply_ascii_reader.h).

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace exao::ply {

enum class Type { None, I8, U8, I16, U16, I32, U32, F32, F64 };

/// The type a PLY type name means (char/int8 ... double/float64); None for any other name.
[[nodiscard]] Type type_of(const std::string& name);
/// Its size in bytes in a binary file; 0 for None.
[[nodiscard]] std::size_t size_of(Type t);
[[nodiscard]] inline bool is_integer(Type t) { return t != Type::None && t != Type::F32 && t != Type::F64; }

struct Property {
  std::string name;
  Type type = Type::None;        // scalar, or a list's items
  Type count_type = Type::None;  // a list's count; None for a scalar
};

struct Element {
  std::string name;
  std::uint64_t count = 0;
  std::vector<Property> properties;
  std::size_t scalar_bytes = 0;  // when no property is a list: the bytes of one entry (binary)
  bool has_list = false;
};

struct Header {
  std::string format;             // "ascii", "binary_little_endian", "binary_big_endian", or as written
  std::vector<Element> elements;
  std::size_t data = 0;           // the first byte after the end_header line
};

/// The header of the PLY whose bytes are `file`; nullopt when it is not one the fast paths take
/// (no "ply" first line, a property before any element, an unknown type or a list whose count is
/// not an integer, an element line without a count, no end_header within 10,000 lines).
[[nodiscard]] std::optional<Header> read_header(std::string_view file);

}  // namespace exao::ply
