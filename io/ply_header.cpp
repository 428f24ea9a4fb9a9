#include "io/ply_header.h"

#include <sstream>
#include <utility>

namespace exao::ply {

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

std::optional<Header> read_header(std::string_view file) {
  std::size_t pos = 0;
  Header header;
  std::string& format = header.format;
  std::vector<Element>& elements = header.elements;
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
      iss >> format;
    } else if (keyword == "element") {
      Element e;
      iss >> e.name >> e.count;
      if (!iss) return std::nullopt;
      elements.push_back(std::move(e));
    } else if (keyword == "property") {
      if (elements.empty()) return std::nullopt;
      Property p;
      std::string type;
      iss >> type;
      if (type == "list") {
        std::string count_type, item_type;
        iss >> count_type >> item_type;
        p.count_type = type_of(count_type);
        p.type = type_of(item_type);
        if (!is_integer(p.count_type) || p.type == Type::None) return std::nullopt;
        elements.back().has_list = true;
      } else {
        p.type = type_of(type);
        if (p.type == Type::None) return std::nullopt;
        elements.back().scalar_bytes += size_of(p.type);
      }
      iss >> p.name;
      elements.back().properties.push_back(std::move(p));
    } else if (keyword == "end_header") {
      end_seen = true;
      break;
    }
  }
  if (!end_seen) return std::nullopt;
  header.data = pos;
  return header;
}

}  // namespace exao::ply
