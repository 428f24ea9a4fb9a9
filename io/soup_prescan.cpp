#include "io/soup_prescan.h"

#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <optional>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "io/file_bytes.h"

namespace exao {
namespace {

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f'; }

// A whole token of decimal digits, as an unsigned count; false when it is anything else or
// beyond 2^62 (far past any file's size, so the size check refuses it either way).
bool parse_count(std::string_view token, std::uint64_t& out) {
  if (token.empty() || token.size() > 18) {
    if (token.empty()) return false;
    for (const char c : token) {
      if (!std::isdigit(static_cast<unsigned char>(c))) return false;
    }
    out = std::uint64_t{1} << 62;
    return true;
  }
  out = 0;
  for (const char c : token) {
    if (!std::isdigit(static_cast<unsigned char>(c))) return false;
    out = out * 10 + static_cast<std::uint64_t>(c - '0');
  }
  return true;
}

// --- PLY -------------------------------------------------------------------------------------

struct PlyProperty {
  bool list = false;
  int count_size = 0;  // bytes of a list's count (binary)
  bool count_signed = false;
  int size = 0;        // bytes of a scalar, or of each list item
};

struct PlyElement {
  std::string name;
  std::uint64_t count = 0;
  std::vector<PlyProperty> properties;
};

// The PLY scalar types CGAL 5.5 reads (CGAL/IO/PLY/PLY_reader.h); 0 for any other name.
int ply_type_size(const std::string& type, bool* is_signed = nullptr) {
  const auto sign = [&](bool s) {
    if (is_signed) *is_signed = s;
  };
  if (type == "char" || type == "int8") return sign(true), 1;
  if (type == "uchar" || type == "uint8") return sign(false), 1;
  if (type == "short" || type == "int16") return sign(true), 2;
  if (type == "ushort" || type == "uint16") return sign(false), 2;
  if (type == "int" || type == "int32") return sign(true), 4;
  if (type == "uint" || type == "uint32") return sign(false), 4;
  if (type == "float" || type == "float32") return sign(true), 4;
  if (type == "double" || type == "float64") return sign(true), 8;
  return 0;
}

std::int64_t read_binary_integer(const unsigned char* p, int size, bool is_signed, bool big_endian) {
  std::uint64_t v = 0;
  for (int i = 0; i < size; ++i) {
    const int byte = big_endian ? i : size - 1 - i;
    v = v << 8 | p[byte];
  }
  if (is_signed && size < 8 && (v >> (8 * size - 1)) != 0) return static_cast<std::int64_t>(v) - (std::int64_t{1} << (8 * size));
  return static_cast<std::int64_t>(v);
}

std::string ply_body_problem_binary(std::string_view body, const std::vector<PlyElement>& elements, bool big_endian) {
  std::size_t pos = 0;
  for (const PlyElement& element : elements) {
    for (std::uint64_t entry = 0; entry < element.count; ++entry) {
      // Worded only when needed: one string per entry took longer than the whole check.
      const auto where_of = [&] { return "element '" + element.name + "' entry " + std::to_string(entry); };
      for (const PlyProperty& p : element.properties) {
        if (!p.list) {
          if (body.size() - pos < static_cast<std::size_t>(p.size)) return "the data ends inside " + where_of();
          pos += static_cast<std::size_t>(p.size);
          continue;
        }
        if (body.size() - pos < static_cast<std::size_t>(p.count_size)) return "the data ends inside " + where_of();
        const std::int64_t count = read_binary_integer(reinterpret_cast<const unsigned char*>(body.data() + pos),
                                                       p.count_size, p.count_signed, big_endian);
        pos += static_cast<std::size_t>(p.count_size);
        const std::size_t left = body.size() - pos;
        if (count < 0 || static_cast<std::uint64_t>(count) > left / static_cast<std::size_t>(p.size)) {
          return where_of() + ": a list of " + std::to_string(count) + " items does not fit in the " +
                 std::to_string(left) + " bytes left";
        }
        pos += static_cast<std::size_t>(count) * static_cast<std::size_t>(p.size);
      }
    }
  }
  return {};
}

std::string ply_body_problem_ascii(std::string_view body, const std::vector<PlyElement>& elements) {
  std::size_t pos = 0;
  // The next whitespace-separated token, or an empty view at the end.
  const auto next = [&]() {
    while (pos < body.size() && is_space(body[pos])) ++pos;
    const std::size_t start = pos;
    while (pos < body.size() && !is_space(body[pos])) ++pos;
    return body.substr(start, pos - start);
  };
  for (const PlyElement& element : elements) {
    for (std::uint64_t entry = 0; entry < element.count; ++entry) {
      for (const PlyProperty& p : element.properties) {
        const std::string_view token = next();
        if (token.empty()) return {};  // too short: CGAL reads zeros and fails on its own
        if (!p.list) continue;
        std::uint64_t count = 0;
        // Worded only when needed, as in the binary scan.
        const auto where = [&] { return "element '" + element.name + "' entry " + std::to_string(entry); };
        if (!parse_count(token, count)) return where() + ": list size '" + std::string(token.substr(0, 20)) + "' is not a count";
        // Each item takes at least one character and one separator.
        const std::size_t left = body.size() - pos;
        if (count > left / 2 + 1) {
          return where() + ": a list of " + std::to_string(count) + " items does not fit in the " +
                 std::to_string(left) + " bytes left";
        }
        for (std::uint64_t i = 0; i < count; ++i) {
          if (next().empty()) return {};
        }
      }
    }
  }
  return {};
}

// What a step of the PLY pre-scan decides: nullopt to read on; otherwise the string for
// ply_problem_in to return (empty when the pre-scan sees no problem and leaves CGAL to judge).
using PlyVerdict = std::optional<std::string>;

// A PLY header as the pre-scan reads it.
struct PlyHeaderScan {
  std::string format;
  std::vector<PlyElement> elements;
  std::size_t data = 0;  // the first byte after the end_header line
};

// A "property" line's words after its keyword (`iss`), added to the last element.
PlyVerdict read_ply_property(std::istringstream& iss, const std::string& where, std::vector<PlyElement>& elements) {
  if (elements.empty()) return where + ": property before any element";
  PlyProperty property;
  std::string type;
  iss >> type;
  if (type == "list") {
    std::string count_type, item_type;
    iss >> count_type >> item_type;
    property.list = true;
    property.count_size = ply_type_size(count_type, &property.count_signed);
    property.size = ply_type_size(item_type);
    if (property.count_size == 0 || property.size == 0) return std::string();  // CGAL judges unknown types
  } else {
    property.size = ply_type_size(type);
    if (property.size == 0) return std::string();
  }
  // CGAL's point reader takes a vertex's x, y and z as a float or a double property and
  // dereferences a null pointer for any other (PLY_element::assign(double&)).
  std::string name;
  iss >> name;
  const std::string& element = elements.back().name;
  const bool real = !property.list && (type == "float" || type == "float32" || type == "double" || type == "float64");
  if ((element == "vertex" || element == "vertices") && (name == "x" || name == "y" || name == "z") && !real) {
    return where + ": vertex coordinate '" + name + "' is " + (property.list ? "a list" : type) +
           " (float or double expected)";
  }
  elements.back().properties.push_back(property);
  return std::nullopt;
}

// The header of the PLY whose bytes are `file`, line by line up to end_header, into `header`;
// nullopt once end_header is read.
PlyVerdict read_ply_header(std::string_view file, PlyHeaderScan& header) {
  std::size_t& pos = header.data;
  // A real header is a few dozen lines; this bounds the scan of a file that has no end_header.
  constexpr std::size_t kMaxHeaderLines = 10'000;
  for (std::size_t number = 1; number <= kMaxHeaderLines && pos < file.size(); ++number) {
    const std::size_t eol = file.find('\n', pos);
    std::string line(file.substr(pos, eol == std::string::npos ? std::string::npos : eol - pos));
    pos = eol == std::string::npos ? file.size() : eol + 1;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::istringstream iss(line);
    std::string keyword;
    iss >> keyword;
    const std::string where = "header line " + std::to_string(number);
    if (number == 1) {
      if (keyword != "ply") return "not a PLY file (no 'ply' signature)";
    } else if (number == 2) {
      if (keyword != "format") return where + ": expected 'format'";
      iss >> header.format;
    } else if (keyword == "element") {
      PlyElement element;
      std::string count;
      iss >> element.name >> count;
      if (!parse_count(count, element.count)) return where + ": element count '" + count.substr(0, 20) + "' is not a count";
      header.elements.push_back(std::move(element));
    } else if (keyword == "property") {
      if (PlyVerdict verdict = read_ply_property(iss, where, header.elements)) return verdict;
    } else if (keyword == "end_header") {
      return std::nullopt;
    }
  }
  return "PLY header has no end_header";
}

// Every entry of an element takes at least one byte per ASCII value, or its scalars' and list
// counts' bytes in binary: the stated counts must fit in the `left` bytes after the header.
// Empty when they do.
std::string ply_count_problem(const std::vector<PlyElement>& elements, bool ascii, std::size_t left) {
  long double needed = 0.0L;
  for (const PlyElement& e : elements) {
    if (e.count > 0 && e.properties.empty()) {
      return "element '" + e.name + "' has " + std::to_string(e.count) + " entries but no properties";
    }
    std::size_t smallest = 0;
    for (const PlyProperty& p : e.properties) smallest += ascii ? 1 : static_cast<std::size_t>(p.list ? p.count_size : p.size);
    needed += static_cast<long double>(e.count) * static_cast<long double>(smallest);
    if (needed > static_cast<long double>(left)) {
      return "element '" + e.name + "' count " + std::to_string(e.count) + " does not fit in the " +
             std::to_string(left) + " bytes after the header";
    }
  }
  return {};
}

// --- OFF -------------------------------------------------------------------------------------

// A cursor over OFF text that skips what CGAL's skip_comment_OFF skips: white space and '#'
// comments to the end of their line.
struct OffText {
  std::string_view text;
  std::size_t pos = 0;

  void skip_comments() {
    for (;;) {
      while (pos < text.size() && is_space(text[pos])) ++pos;
      if (pos < text.size() && text[pos] == '#') {
        while (pos < text.size() && text[pos] != '\n') ++pos;
      } else {
        return;
      }
    }
  }
  std::string_view line() {
    const std::size_t start = pos;
    while (pos < text.size() && text[pos] != '\n') ++pos;
    std::string_view out = text.substr(start, pos - start);
    if (pos < text.size()) ++pos;
    if (const std::size_t hash = out.find('#'); hash != std::string_view::npos) out = out.substr(0, hash);
    return out;
  }
  std::string_view word() {
    while (pos < text.size() && is_space(text[pos])) ++pos;
    const std::size_t start = pos;
    while (pos < text.size() && !is_space(text[pos]) && text[pos] != '#') ++pos;
    return text.substr(start, pos - start);
  }
};

// Every number at the front of a line, as CGAL reads them (istream >> double until one fails).
std::vector<double> numbers_of(std::string_view line) {
  std::vector<double> out;
  std::istringstream in{std::string(line)};
  double d = 0.0;
  while (in >> d) out.push_back(d);
  return out;
}

struct OffHeader {
  bool textures = false, colours = false, normals = false, homogeneous = false, dimensional = false;
};

// CGAL's colour entries (0, 1, 3 or 4 numbers after what the header promises) index its array of
// numbers unchecked, and a single entry indexes a 149-colour map, so each is checked here; once
// one vertex (or face) had a colour, CGAL expects one on every later line.
std::string colour_problem(const std::vector<double>& numbers, std::size_t first, bool& seen, const std::string& where) {
  const std::size_t entries = numbers.size() - first;
  if (entries != 0 && entries != 1 && entries != 3 && entries != 4) {
    return where + ": " + std::to_string(entries) + " colour numbers (0, 1, 3 or 4 expected)";
  }
  if (entries == 0 && seen) return where + ": no colour, after lines that had one";
  if (entries == 1 && !(numbers[first] >= 0.0 && numbers[first] < 1e9)) return where + ": colour index out of range";
  if (entries != 0) seen = true;
  return {};
}

std::string off_text_problem(OffText& in, const OffHeader& h, std::uint64_t vertices, std::uint64_t faces) {
  const std::size_t coordinates = h.homogeneous ? 4 : 3;
  std::size_t per_vertex = coordinates + (h.normals ? coordinates : 0);
  const std::size_t colour_at = per_vertex;
  per_vertex += h.textures ? coordinates - 1 : 0;
  bool vertex_colours = false;
  for (std::uint64_t v = 0; v < vertices; ++v) {
    in.skip_comments();
    if (in.pos >= in.text.size()) return {};  // too short: CGAL fails on its own
    const std::vector<double> numbers = numbers_of(in.line());
    const std::string where = "vertex " + std::to_string(v);
    if (numbers.size() < per_vertex) {
      return where + " has " + std::to_string(numbers.size()) + " numbers, the header asks for " + std::to_string(per_vertex);
    }
    if (h.colours) {
      std::vector<double> without_textures(numbers.begin(), numbers.end() - static_cast<std::ptrdiff_t>(per_vertex - colour_at));
      if (auto problem = colour_problem(without_textures, colour_at, vertex_colours, where); !problem.empty()) return problem;
    }
  }
  bool face_colours = false;
  for (std::uint64_t f = 0; f < faces; ++f) {
    in.skip_comments();
    if (in.pos >= in.text.size()) return {};
    const std::size_t left = in.text.size() - in.pos;
    const std::vector<double> numbers = numbers_of(in.line());
    const std::string where = "face " + std::to_string(f);
    if (numbers.empty()) return {};  // CGAL refuses it
    const double size = numbers[0];
    // CGAL sizes the face from its first number, then reads that many from the same line.
    if (!(size >= 0.0 && size <= static_cast<double>(numbers.size() - 1) && size <= static_cast<double>(left))) {
      return where + " says it has " + std::to_string(size).substr(0, 24) + " vertices but its line holds " +
             std::to_string(numbers.size() - 1) + " numbers";
    }
    if (h.colours) {
      if (auto problem = colour_problem(numbers, static_cast<std::size_t>(size) + 1, face_colours, where); !problem.empty()) {
        return problem;
      }
    }
  }
  return {};
}

std::int64_t big_endian_i32(std::string_view bytes, std::size_t pos) {
  return read_binary_integer(reinterpret_cast<const unsigned char*>(bytes.data() + pos), 4, true, true);
}

// OFF BINARY as CGAL 5.5's polygon-soup reader takes it (CGAL/IO/OFF.h, File_scanner_OFF.h):
// big-endian int32 counts; float32 vertices, each with its normal and texture when the header
// says so (colours are not read); faces are an int32 size and that many int32 indices.
std::string off_binary_problem(std::string_view data, const OffHeader& h) {
  std::size_t pos = 0;
  const auto take_i32 = [&](std::int64_t& out) {
    if (data.size() - pos < 4) return false;
    out = big_endian_i32(data, pos);
    pos += 4;
    return true;
  };
  std::int64_t dimension = 3, vertices = 0, faces = 0, edges = 0;
  if (h.dimensional && !take_i32(dimension)) return "the binary header ends early";
  if (!take_i32(vertices) || !take_i32(faces) || !take_i32(edges)) return "the binary header ends early";
  const std::size_t coordinates = h.homogeneous ? 4 : 3;
  const std::size_t vertex_bytes = 4 * (coordinates + (h.normals ? coordinates : 0) + (h.textures ? coordinates - 1 : 0));
  const std::size_t left = data.size() - pos;
  if (vertices < 0 || faces < 0 || static_cast<std::uint64_t>(vertices) > left / vertex_bytes ||
      static_cast<std::uint64_t>(faces) > (left - static_cast<std::size_t>(vertices) * vertex_bytes) / 4) {
    return "binary header counts " + std::to_string(vertices) + " vertices and " + std::to_string(faces) +
           " faces do not fit in the " + std::to_string(left) + " bytes that follow";
  }
  pos += static_cast<std::size_t>(vertices) * vertex_bytes;
  for (std::int64_t f = 0; f < faces; ++f) {
    std::int64_t size = 0;
    if (!take_i32(size)) return {};  // too short: CGAL fails on its own
    if (size < 0 || static_cast<std::uint64_t>(size) > (data.size() - pos) / 4) {
      return "face " + std::to_string(f) + " says it has " + std::to_string(size) + " vertices, more than the " +
             std::to_string(data.size() - pos) + " bytes left hold";
    }
    pos += static_cast<std::size_t>(4 * size);
  }
  return {};
}

}  // namespace

std::string ply_problem(const std::string& path) {
  std::string file;
  if (!read_file_bytes(path, file)) return {};  // the reader reports it
  return ply_problem_in(file);
}

std::string ply_problem_in(std::string_view file) {
  PlyHeaderScan header;
  if (PlyVerdict verdict = read_ply_header(file, header)) return *std::move(verdict);
  const bool ascii = header.format == "ascii";
  if (!ascii && header.format != "binary_little_endian" && header.format != "binary_big_endian") return {};
  const std::size_t left = file.size() - header.data;
  if (std::string problem = ply_count_problem(header.elements, ascii, left); !problem.empty()) return problem;
  const std::string_view body = file.substr(header.data);
  return ascii ? ply_body_problem_ascii(body, header.elements)
               : ply_body_problem_binary(body, header.elements, header.format == "binary_big_endian");
}

std::string off_problem(const std::string& path) {
  std::string file;
  if (!read_file_bytes(path, file)) return {};
  OffText in{file};
  in.skip_comments();
  const std::string_view keyword = in.word();
  // The keyword is [ST][C][N][4][n]OFF; anything else (SKEL, no header) CGAL judges itself.
  OffHeader h;
  std::size_t j = 0;
  if (keyword.substr(j, 2) == "ST") h.textures = true, j += 2;
  if (keyword.substr(j, 1) == "C") h.colours = true, j += 1;
  if (keyword.substr(j, 1) == "N") h.normals = true, j += 1;
  if (keyword.substr(j, 1) == "4") h.homogeneous = true, j += 1;
  if (keyword.substr(j, 1) == "n") h.dimensional = true, j += 1;
  if (keyword.substr(j) != "OFF") return {};
  // CGAL 5.5 reads texture coordinates after an offset that only a colour-capable header sets:
  // without `C`, it indexes its numbers with an uninitialised value.
  if (h.textures && !h.colours) return "ST" + std::string(keyword.substr(2)) + " (textures without colours) is not supported by CGAL's OFF reader";
  in.skip_comments();
  if (in.pos < file.size() && !std::isdigit(static_cast<unsigned char>(file[in.pos])) && file[in.pos] != '-') {
    if (in.word() != "BINARY") return {};
    while (in.pos < file.size() && file[in.pos] != '\n') ++in.pos;
    if (in.pos < file.size()) ++in.pos;
    return off_binary_problem(std::string_view(file).substr(in.pos), h);
  }
  std::vector<std::int64_t> counts;
  for (int i = 0; i < (h.dimensional ? 4 : 3); ++i) {
    in.skip_comments();
    const std::string_view word = in.word();
    // CGAL reads an int from the front of the word, as this does.
    char* end = nullptr;
    const std::string text(word);
    const long long value = std::strtoll(text.c_str(), &end, 10);
    if (end == text.c_str()) return {};  // not a number: CGAL refuses the file
    counts.push_back(value);
    if (end != text.c_str() + text.size()) break;  // CGAL stops reading counts here
  }
  if (h.dimensional && !counts.empty()) counts.erase(counts.begin());
  for (std::size_t i = 0; i < counts.size() && i < 2; ++i) {
    if (counts[i] < 0 || static_cast<std::uint64_t>(counts[i]) > file.size()) {
      return "header count " + std::to_string(counts[i]) + " does not fit in a file of " + std::to_string(file.size()) + " bytes";
    }
  }
  if (counts.size() < 3) return {};  // CGAL fails before it reads a vertex
  return off_text_problem(in, h, static_cast<std::uint64_t>(counts[0]), static_cast<std::uint64_t>(counts[1]));
}

}  // namespace exao
