// OBJ, PLY, OFF and STL through CGAL's polygon-soup reader. These formats carry no notion of
// sidedness, so every triangle blocks rays from both sides; polygons are fan-triangulated.

#include "io/polygon_soup_loader.h"
#include "io/obj_ignored_statements.h"

#include <CGAL/IO/polygon_soup_io.h>
#include <CGAL/Simple_cartesian.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cstdint>
#include <exception>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>

#include "core/file_kind.h"
#include "io/file_bytes.h"
#include "io/mapped_file.h"
#include "io/obj_ascii_reader.h"
#include "io/off_ascii_reader.h"
#include "io/ply_ascii_reader.h"
#include "io/ply_binary_reader.h"
#include "io/stl_binary_reader.h"
#include "io/soup_prescan.h"

namespace exao {
namespace {

using Point = CGAL::Simple_cartesian<double>::Point_3;
using Polygon = std::vector<std::size_t>;

std::string lowercase_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}


// CGAL's reader says only "false" when it refuses a file (its verbose mode prints to stderr,
// which library code must not do). For OBJ, the most common hand-made format, this scan finds
// the first reason in CGAL's own terms so the error can name it.
std::string explain_obj_failure(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  std::size_t line_number = 0;
  std::size_t vertices = 0;
  std::size_t faces = 0;
  long long worst_index = 0;  // the first face index found beyond the vertices, as written
  std::size_t worst_face = 0;
  std::vector<long long> face_max;  // largest positive index per face, checked at the end
  while (std::getline(in, line)) {
    ++line_number;
    std::istringstream iss(line);
    std::string keyword;
    if (!(iss >> keyword)) continue;
    if (keyword == "v") {
      double x = 0.0;
      double y = 0.0;
      double z = 0.0;
      if (!(iss >> x >> y >> z)) return "line " + std::to_string(line_number) + ": bad vertex";
      ++vertices;
    } else if (keyword == "f") {
      ++faces;
      long long i = 0;
      long long largest = 0;
      while (iss >> i) {
        if (i < 0 && -i > static_cast<long long>(vertices) && worst_face == 0) {
          worst_face = faces;
          worst_index = i;
        }
        largest = std::max(largest, i);
        iss.ignore(256, ' ');
      }
      face_max.push_back(largest);
    } else if (keyword.front() != '#' &&
               std::find(kObjIgnoredStatements.begin(), kObjIgnoredStatements.end(), keyword) ==
                   kObjIgnoredStatements.end()) {
      return "line " + std::to_string(line_number) + ": unsupported statement '" +
             keyword.substr(0, 20) + "'";
    }
  }
  for (std::size_t f = 0; f < face_max.size() && worst_face == 0; ++f) {
    if (face_max[f] > static_cast<long long>(vertices)) {
      worst_face = f + 1;
      worst_index = face_max[f];
    }
  }
  if (worst_face != 0) {
    return "face " + std::to_string(worst_face) + " refers to vertex " +
           std::to_string(worst_index) + ", file has " + std::to_string(vertices);
  }
  if (vertices == 0 || faces == 0) return "no triangles";
  return "not a readable OBJ file";
}

// A load's progress in bytes: reading the file is the first half, making the scene the second.
struct LoadProgress {
  const ProgressCallback& progress;
  [[nodiscard]] ProgressCallback reading() const {
    if (!progress) return {};
    return [&p = progress](std::size_t done, std::size_t total) { p(done, 2 * total); };
  }
  [[nodiscard]] ProgressCallback parsing() const {
    if (!progress) return {};
    return [&p = progress](std::size_t done, std::size_t total) { p(total + done, 2 * total); };
  }
};

// A file buffer that tells how far its reader has come: (bytes handed out, file size), at each
// refill, so that CGAL's readers, which take a stream, report progress.
class ProgressFileBuffer : public std::filebuf {
 public:
  ProgressFileBuffer(const ProgressCallback& progress, std::size_t size) : progress_(progress), size_(size) {}

 protected:
  int_type underflow() override {
    const int_type c = std::filebuf::underflow();
    if (c != traits_type::eof()) {
      position_ += static_cast<std::size_t>(egptr() - eback());
      if (progress_) progress_(std::min(position_, size_), size_);
    }
    return c;
  }
  pos_type seekoff(off_type offset, std::ios_base::seekdir way, std::ios_base::openmode which) override {
    return moved(std::filebuf::seekoff(offset, way, which));
  }
  pos_type seekpos(pos_type position, std::ios_base::openmode which) override {
    return moved(std::filebuf::seekpos(position, which));
  }

 private:
  pos_type moved(pos_type to) {
    if (to != pos_type(off_type(-1))) position_ = static_cast<std::size_t>(off_type(to));
    return to;
  }
  const ProgressCallback& progress_;
  std::size_t size_;
  std::size_t position_ = 0;
};

// CGAL::IO::read_polygon_soup(path, ...) as CGAL 5.5 runs it (CGAL/IO/polygon_soup_io.h and
// each format's read_X(file name)), on streams whose buffer reports progress: the same stream
// modes, and STL's second, ASCII attempt.
bool read_with_cgal(const std::string& path, const std::string& ext, std::vector<Point>& points,
                    std::vector<Polygon>& polygons, const ProgressCallback& progress) {
  std::error_code error;
  const auto size = static_cast<std::size_t>(std::filesystem::file_size(path, error));
  const auto params = CGAL::parameters::verbose(false);
  // A file that does not open gives a failed stream, as an ifstream that does not open.
  const auto read = [&](std::ios_base::openmode mode, auto&& reader) {
    ProgressFileBuffer buffer(progress, error ? 0 : size);
    std::istream in(&buffer);
    if (!buffer.open(path, std::ios::in | mode)) in.setstate(std::ios::failbit);
    return reader(in);
  };
  if (ext == ".obj") {
    return read({}, [&](std::istream& in) {
      CGAL::IO::set_mode(in, CGAL::IO::ASCII);
      return CGAL::IO::read_OBJ(in, points, polygons, params);
    });
  }
  if (ext == ".off") return read({}, [&](std::istream& in) { return CGAL::IO::read_OFF(in, points, polygons, params); });
  if (ext == ".ply") {
    return read(std::ios::binary, [&](std::istream& in) {
      CGAL::IO::set_mode(in, CGAL::IO::BINARY);
      return CGAL::IO::read_PLY(in, points, polygons, params);
    });
  }
  const bool binary = read(std::ios::binary, [&](std::istream& in) {
    CGAL::IO::set_mode(in, CGAL::IO::BINARY);
    return CGAL::IO::read_STL(in, points, polygons, params);
  });
  if (binary) return true;
  points.clear();
  polygons.clear();
  return read({}, [&](std::istream& in) {
    CGAL::IO::set_mode(in, CGAL::IO::ASCII);
    return CGAL::IO::read_STL(in, points, polygons, CGAL::parameters::verbose(false).use_binary_mode(false));
  });
}

// The PLY and STL layouts read straight into the scene (io/ply_binary_reader.h,
// io/ply_ascii_reader.h, io/stl_binary_reader.h), from the mapped file (a read into a buffer
// cost a third of a binary PLY's load: zeroing it, then the copy); nullopt for any other file,
// which CGAL then reads. PLY's pre-scan (io/soup_prescan.h) reads the same bytes.
std::optional<Result<Scene>> read_directly(const std::string& path, const std::string& ext,
                                           const LoadProgress& progress) {
  const MappedFile mapped(path);
  std::string copy;  // where the file does not map
  if (!mapped.ok() && !read_file_bytes(path, copy, progress.reading())) return Result<Scene>(fail("cannot read the file"));
  const std::string_view file = mapped.ok() ? mapped.bytes() : std::string_view(copy);
  if (ext == ".stl") return read_binary_stl(file, progress.parsing());
  if (const std::string problem = ply_problem_in(file); !problem.empty()) return Result<Scene>(fail(problem));
  if (std::optional<Result<Scene>> scene = read_binary_ply(file, progress.parsing())) return scene;
  return read_ascii_ply(file, progress.parsing());
}

// The fast paths (SoupPath::Fast): OBJ and OFF from the mapped file, PLY and STL from one read;
// nullopt for a file none of them takes.
std::optional<Result<Scene>> read_fast(const std::string& path, const std::string& ext, const ProgressCallback& progress) {
  // (A file that does not map, or that the OBJ or OFF fast path does not take, is CGAL's to read
  // or refuse, after OFF's pre-scan.)
  if (ext == ".obj" || ext == ".off") {
    const MappedFile file(path);
    if (!file.ok()) return std::nullopt;
    return ext == ".obj" ? read_ascii_obj(file.bytes(), progress) : read_ascii_off(file.bytes(), progress);
  }
  // CGAL's OFF and PLY readers trust the counts a file states (io/soup_prescan.h).
  return read_directly(path, ext, LoadProgress{progress});
}

// Why CGAL refused the file, as far as exao can tell: for OBJ the first reason in CGAL's terms,
// for the others the format, and whether CGAL had read any points and faces at all.
std::string cgal_refusal(const std::string& path, const std::string& ext, bool nothing_read) {
  if (ext == ".obj") return explain_obj_failure(path);
  std::string format = ext.substr(1);
  for (char& c : format) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  if (nothing_read) return "not a readable " + format + " file, or it has no faces";
  return "not a readable " + format + " file";
}

// The first face index past the `vertex_count` vertices, as an error quoting the file's
// numbering (its first vertex is `base`); empty when every index is in range. CGAL checks OBJ
// indices loosely (one past the end passes) and PLY/OFF indices not at all.
std::string index_problem(const std::vector<Polygon>& polygons, std::size_t vertex_count, long long base) {
  for (std::size_t f = 0; f < polygons.size(); ++f) {
    for (const std::size_t v : polygons[f]) {
      if (v >= vertex_count) {
        return "face " + std::to_string(f + 1) + " refers to vertex " + std::to_string(static_cast<long long>(v) + base) +
               ", file has " + std::to_string(vertex_count);
      }
    }
  }
  return {};
}

// The polygons as two-sided triangles; polygons of fewer than 3 corners skipped and counted.
Result<Scene> scene_of(const std::vector<Point>& points, const std::vector<Polygon>& polygons) {
  Scene scene;
  std::size_t too_small = 0;
  std::size_t triangles = 0;
  for (const Polygon& polygon : polygons) {
    if (polygon.size() >= 3) triangles += polygon.size() - 2;
  }
  scene.reserve(triangles);
  const auto at = [&](std::size_t i) {
    const Point& p = points[i];
    return glm::vec3(static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z()));
  };
  for (const Polygon& polygon : polygons) {
    if (polygon.size() < 3) {
      ++too_small;
      continue;
    }
    // Fan from the first corner: exact for the convex polygons these formats usually hold.
    const glm::vec3 first = at(polygon[0]);
    for (std::size_t k = 1; k + 1 < polygon.size(); ++k) {
      scene.add_triangle(first, at(polygon[k]), at(polygon[k + 1]), true, -1);
    }
  }
  if (too_small > 0) scene.report.notes.push_back(std::to_string(too_small) + " faces with fewer than 3 vertices skipped");
  if (scene.triangle_count() == 0) return fail("no triangles");
  return scene;
}

Result<Scene> load(const std::string& path, const ProgressCallback& progress, SoupPath reader) {
  if (const std::string problem = not_a_regular_file(path); !problem.empty()) return fail(problem);
  const std::string ext = lowercase_extension(path);
  if (ext != ".obj" && ext != ".ply" && ext != ".off" && ext != ".stl") {
    return fail("not an OBJ, PLY, OFF or STL file");
  }
  if (reader == SoupPath::Fast) {
    if (std::optional<Result<Scene>> scene = read_fast(path, ext, progress)) return std::move(*scene);
  }
  // (The fast path has run PLY's pre-scan already.)
  const std::string problem = ext == ".off"                                ? off_problem(path)
                              : ext == ".ply" && reader == SoupPath::Cgal ? ply_problem(path)
                                                                          : std::string();
  if (!problem.empty()) return fail(problem);

  std::vector<Point> points;
  std::vector<Polygon> polygons;
  if (!read_with_cgal(path, ext, points, polygons, progress)) {
    return fail(cgal_refusal(path, ext, points.empty() || polygons.empty()));
  }
  // OBJ numbers vertices from 1; the other formats from 0. Errors quote the file's numbering.
  const long long base = ext == ".obj" ? 1 : 0;
  if (const std::string bad_index = index_problem(polygons, points.size(), base); !bad_index.empty()) {
    return fail(bad_index);
  }
  return scene_of(points, polygons);
}

}  // namespace

Result<Scene> load_polygon_soup(const std::string& path, const ProgressCallback& progress, SoupPath reader) {
  Result<Scene> scene;
  // CGAL reports some failures by throwing (its assertions, bad_alloc on a hostile count).
  try {
    scene = load(path, progress, reader);
  } catch (const std::exception& e) {
    std::string what = e.what();
    for (char& c : what) {
      if (c == '\n' || c == '\r') c = ' ';
    }
    scene = fail("cannot read: " + what.substr(0, 200));
  } catch (...) {
    scene = fail("cannot read: unknown error");
  }
  if (!scene) return fail(path + ": " + scene.error().message);
  scene->name = std::filesystem::path(path).stem().string();
  return scene;
}

}  // namespace exao
