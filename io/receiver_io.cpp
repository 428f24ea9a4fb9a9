#include "io/receiver_io.h"

#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <CGAL/Point_set_3.h>
#include <CGAL/Point_set_3/IO.h>
#include <CGAL/Simple_cartesian.h>

#include "core/atomic_write.h"
#include "core/coordinate_limit.h"
#include "core/file_kind.h"
#include "io/soup_prescan.h"

namespace exao {
namespace {

constexpr const char* kBeyondLimit = "a coordinate is beyond +-1e17, the largest exao accepts";

bool finite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

Result<std::vector<Receiver>> load_text(const std::string& path) {
  std::ifstream in(path);
  if (!in) return fail(path + ": cannot open");
  std::vector<Receiver> receivers;
  std::string line;
  std::uint64_t number = 0;
  while (std::getline(in, line)) {
    ++number;
    const auto first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    std::istringstream fields(line);
    Receiver r;
    r.key = number;
    if (!(fields >> r.position.x >> r.position.y >> r.position.z >> r.normal.x >> r.normal.y >> r.normal.z)) {
      return fail(path + ": line " + std::to_string(number) + ": expected 'x y z nx ny nz [key]'");
    }
    std::string key;
    if (fields >> key) {
      try {
        std::size_t used = 0;
        r.key = std::stoull(key, &used);
        if (used != key.size()) throw std::invalid_argument(key);
      } catch (const std::exception&) {
        return fail(path + ": line " + std::to_string(number) + ": key '" + key + "' is not a non-negative integer");
      }
      std::string extra;
      if (fields >> extra) return fail(path + ": line " + std::to_string(number) + ": unexpected '" + extra + "'");
    }
    if (!finite(r.position) || !finite(r.normal)) return fail(path + ": line " + std::to_string(number) + ": NaN or infinite value");
    if (!within_coordinate_limit(r.position)) return fail(path + ": line " + std::to_string(number) + ": " + kBeyondLimit);
    if (glm::dot(r.normal, r.normal) == 0.0f) return fail(path + ": line " + std::to_string(number) + ": zero normal");
    receivers.push_back(r);
  }
  return receivers;
}

Result<std::vector<Receiver>> load_ply(const std::string& path) {
  using Kernel = CGAL::Simple_cartesian<double>;
  CGAL::Point_set_3<Kernel::Point_3, Kernel::Vector_3> points;
  std::ifstream in(path, std::ios::binary);
  if (!in) return fail(path + ": cannot open");
  // CGAL's PLY reader trusts the counts a file states (io/soup_prescan.h).
  if (const std::string problem = ply_problem(path); !problem.empty()) return fail(path + ": " + problem);
  bool ok = false;
  try {
    ok = CGAL::IO::read_PLY(in, points);
  } catch (const std::exception& e) {
    return fail(path + ": not a readable PLY point cloud (" + e.what() + ")");
  }
  if (!ok) return fail(path + ": not a readable PLY point cloud");
  if (!points.has_normal_map()) return fail(path + ": the PLY has no normals (nx, ny, nz)");
  std::vector<Receiver> receivers;
  std::uint64_t index = 0;
  for (const auto& item : points) {
    const auto& p = points.point(item);
    const auto& n = points.normal(item);
    Receiver r{{static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z())},
               {static_cast<float>(n.x()), static_cast<float>(n.y()), static_cast<float>(n.z())},
               index};
    if (!finite(r.position) || !finite(r.normal)) return fail(path + ": vertex " + std::to_string(index) + ": NaN or infinite value");
    if (!within_coordinate_limit(r.position)) return fail(path + ": vertex " + std::to_string(index) + ": " + kBeyondLimit);
    if (glm::dot(r.normal, r.normal) == 0.0f) return fail(path + ": vertex " + std::to_string(index) + ": zero normal");
    receivers.push_back(r);
    ++index;
  }
  return receivers;
}

}  // namespace

Result<std::vector<Receiver>> load_receivers(const std::string& path) {
  if (const std::string problem = not_a_regular_file(path); !problem.empty()) return fail(path + ": " + problem);
  std::string extension = std::filesystem::path(path).extension().string();
  for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  Result<std::vector<Receiver>> receivers = extension == ".ply" ? load_ply(path) : load_text(path);
  if (receivers && receivers->empty()) return fail(path + ": no receivers");
  return receivers;
}

Result<void> save_values(const std::vector<float>& values, const std::string& path) {
  return write_atomically(path, [&](const std::string& temp) -> Result<void> {
    std::FILE* file = std::fopen(temp.c_str(), "w");
    if (!file) return fail(path + ": cannot open for writing: " + system_reason());
    bool ok = true;
    for (const float v : values) ok = ok && std::fprintf(file, "%.9g\n", static_cast<double>(v)) > 0;
    ok = ok && std::fflush(file) == 0;
    std::string reason = ok ? std::string() : system_reason();
    if (std::fclose(file) != 0 && ok) {
      ok = false;
      reason = system_reason();
    }
    if (!ok) return fail(path + ": write failed: " + reason);
    return {};
  });
}

}  // namespace exao
