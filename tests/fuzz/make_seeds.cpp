// Seed inputs for the fuzz targets, written from the built-in scenes (no file needed): every
// format the targets read, in each of its variants (glTF with a data URI, GLB, OBJ with a quad,
// ASCII and binary PLY, OFF and COFF, ASCII and binary STL, text and PLY receivers). Small on
// purpose (at most kMaxTriangles triangles a scene): AFL++ mutates small files fastest.
// Usage: exao_fuzz_seeds OUT_FOLDER (scripts/fuzz-seeds.sh adds small real scenes).

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "io/load_scene.h"

namespace {

namespace fs = std::filesystem;
using exao::Scene;

constexpr std::size_t kMaxTriangles = 64;

void write(const fs::path& path, const std::string& bytes) {
  fs::create_directories(path.parent_path());
  std::ofstream(path, std::ios::binary) << bytes;
}

template <class T>
void append(std::string& out, const T& value) {
  out.append(reinterpret_cast<const char*>(&value), sizeof value);  // little-endian (x86, ARM)
}

std::string base64(const std::string& bytes) {
  static constexpr char kDigits[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    std::uint32_t v = static_cast<std::uint8_t>(bytes[i]) << 16;
    if (i + 1 < bytes.size()) v |= static_cast<std::uint32_t>(static_cast<std::uint8_t>(bytes[i + 1])) << 8;
    if (i + 2 < bytes.size()) v |= static_cast<std::uint8_t>(bytes[i + 2]);
    out += kDigits[v >> 18 & 63];
    out += kDigits[v >> 12 & 63];
    out += i + 1 < bytes.size() ? kDigits[v >> 6 & 63] : '=';
    out += i + 2 < bytes.size() ? kDigits[v & 63] : '=';
  }
  return out;
}

std::size_t triangles(const Scene& s) { return std::min(s.triangle_count(), kMaxTriangles); }

std::string obj(const Scene& s) {
  std::ostringstream out;
  out << "# " << s.name << "\no " << s.name << "\n";
  for (std::size_t t = 0; t < triangles(s); ++t) {
    for (const glm::vec3& v : s.triangle(t)) out << "v " << v.x << ' ' << v.y << ' ' << v.z << '\n';
  }
  out << "vn 0 0 1\nvt 0 0\ng faces\n";
  for (std::size_t t = 0; t < triangles(s); ++t) out << "f " << 3 * t + 1 << ' ' << 3 * t + 2 << "/1 " << 3 * t + 3 << "/1/1\n";
  if (triangles(s) >= 2) out << "f 1 2 3 4\nf -1 -2 -3\n";  // a quad, negative indices
  return out.str();
}

std::string ply(const Scene& s, bool binary) {
  const std::size_t n = triangles(s);
  std::ostringstream header;
  header << "ply\nformat " << (binary ? "binary_little_endian" : "ascii") << " 1.0\ncomment " << s.name
         << "\nelement vertex " << 3 * n << "\nproperty float x\nproperty float y\nproperty float z\nelement face " << n
         << "\nproperty list uchar int vertex_indices\nend_header\n";
  std::string out = header.str();
  std::ostringstream text;
  for (std::size_t t = 0; t < n; ++t) {
    for (const glm::vec3& v : s.triangle(t)) {
      if (binary) {
        append(out, v.x), append(out, v.y), append(out, v.z);
      } else {
        text << v.x << ' ' << v.y << ' ' << v.z << '\n';
      }
    }
  }
  for (std::size_t t = 0; t < n; ++t) {
    if (binary) {
      append(out, std::uint8_t{3});
      for (int k = 0; k < 3; ++k) append(out, static_cast<std::int32_t>(3 * t + k));
    } else {
      text << "3 " << 3 * t << ' ' << 3 * t + 1 << ' ' << 3 * t + 2 << '\n';
    }
  }
  return out + text.str();
}

std::string off(const Scene& s, bool colours) {
  const std::size_t n = triangles(s);
  std::ostringstream out;
  out << (colours ? "COFF" : "OFF") << "\n# " << s.name << "\n" << 3 * n << ' ' << n << " 0\n";
  for (std::size_t t = 0; t < n; ++t) {
    for (const glm::vec3& v : s.triangle(t)) out << v.x << ' ' << v.y << ' ' << v.z << (colours ? " 255 128 0 255" : "") << '\n';
  }
  for (std::size_t t = 0; t < n; ++t) out << "3 " << 3 * t << ' ' << 3 * t + 1 << ' ' << 3 * t + 2 << (colours ? " 0.5 0.5 0.5" : "") << '\n';
  return out.str();
}

std::string stl(const Scene& s, bool binary) {
  const std::size_t n = triangles(s);
  if (binary) {
    std::string out(80, ' ');
    out.replace(0, s.name.size(), s.name);
    append(out, static_cast<std::uint32_t>(n));
    for (std::size_t t = 0; t < n; ++t) {
      for (int k = 0; k < 3; ++k) append(out, 0.0f);
      for (const glm::vec3& v : s.triangle(t)) append(out, v.x), append(out, v.y), append(out, v.z);
      append(out, std::uint16_t{0});
    }
    return out;
  }
  std::ostringstream out;
  out << "solid " << s.name << "\n";
  for (std::size_t t = 0; t < n; ++t) {
    out << " facet normal 0 0 1\n  outer loop\n";
    for (const glm::vec3& v : s.triangle(t)) out << "   vertex " << v.x << ' ' << v.y << ' ' << v.z << '\n';
    out << "  endloop\n endfacet\n";
  }
  out << "endsolid " << s.name << "\n";
  return out.str();
}

// glTF 2.0: positions and uint16 indices in one buffer, a double-sided material, a camera node.
std::string gltf_json(const Scene& s, std::size_t& bytes, std::string& buffer, bool glb) {
  const std::size_t n = triangles(s);
  glm::vec3 lo(1e30f), hi(-1e30f);
  for (std::size_t t = 0; t < n; ++t) {
    for (const glm::vec3& v : s.triangle(t)) {
      append(buffer, v.x), append(buffer, v.y), append(buffer, v.z);
      lo = glm::min(lo, v);
      hi = glm::max(hi, v);
    }
  }
  const std::size_t positions = buffer.size();
  for (std::size_t i = 0; i < 3 * n; ++i) append(buffer, static_cast<std::uint16_t>(i));
  while (buffer.size() % 4 != 0) buffer += '\0';
  bytes = buffer.size();
  std::ostringstream j;
  j << R"({"asset":{"version":"2.0","generator":"exao_fuzz_seeds"},"scene":0,"scenes":[{"nodes":[0,1]}],)"
    << R"("nodes":[{"mesh":0,"name":")" << s.name << R"(","rotation":[0,0,0,1],"scale":[1,1,1]},)"
    << R"({"camera":0,"translation":[0,1,5]}],"cameras":[{"type":"perspective","perspective":{"yfov":0.8,"znear":0.01}}],)"
    << R"("materials":[{"doubleSided":true}],"meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":1,"material":0,"mode":4}]}],)"
    << R"("accessors":[{"bufferView":0,"componentType":5126,"count":)" << 3 * n << R"(,"type":"VEC3","min":[)" << lo.x << ','
    << lo.y << ',' << lo.z << "],\"max\":[" << hi.x << ',' << hi.y << ',' << hi.z << "]},"
    << R"({"bufferView":1,"componentType":5123,"count":)" << 3 * n << R"(,"type":"SCALAR"}],)"
    << R"("bufferViews":[{"buffer":0,"byteLength":)" << positions << R"(},{"buffer":0,"byteOffset":)" << positions
    << R"(,"byteLength":)" << 6 * n << "}],"
    << R"("buffers":[{"byteLength":)" << bytes;
  if (!glb) j << R"(,"uri":"data:application/octet-stream;base64,)" << base64(buffer) << '"';
  j << "}],\"extras\":{\"seed\":[1,[2,{\"a\":\"[\\\"\"}]]}}";
  return j.str();
}

std::string gltf(const Scene& s) {
  std::size_t bytes = 0;
  std::string buffer;
  return gltf_json(s, bytes, buffer, false);
}

std::string glb(const Scene& s) {
  std::size_t bytes = 0;
  std::string buffer;
  std::string json = gltf_json(s, bytes, buffer, true);
  while (json.size() % 4 != 0) json += ' ';
  std::string out = "glTF";
  append(out, std::uint32_t{2});
  append(out, static_cast<std::uint32_t>(12 + 8 + json.size() + 8 + buffer.size()));
  append(out, static_cast<std::uint32_t>(json.size()));
  out += "JSON" + json;
  append(out, static_cast<std::uint32_t>(buffer.size()));
  out += std::string("BIN\0", 4) + buffer;
  return out;
}

// Receivers at triangle centres, along their normals.
std::string points_text(const Scene& s) {
  std::ostringstream out;
  out << "# x y z nx ny nz [key]\n";
  for (std::size_t t = 0; t < triangles(s); ++t) {
    const auto tri = s.triangle(t);
    const glm::vec3 c = (tri[0] + tri[1] + tri[2]) / 3.0f;
    const glm::vec3 n = glm::cross(tri[1] - tri[0], tri[2] - tri[0]);
    out << c.x << ' ' << c.y << ' ' << c.z << ' ' << n.x << ' ' << n.y << ' ' << n.z;
    if (t % 2 == 0) out << ' ' << 1000 + t;
    out << '\n';
  }
  return out.str();
}

std::string points_ply(const Scene& s, bool binary) {
  const std::size_t n = triangles(s);
  std::string out = std::string("ply\nformat ") + (binary ? "binary_little_endian" : "ascii") + " 1.0\nelement vertex " +
                    std::to_string(n) +
                    "\nproperty float x\nproperty float y\nproperty float z\nproperty float nx\nproperty float ny\n"
                    "property float nz\nend_header\n";
  std::ostringstream text;
  for (std::size_t t = 0; t < n; ++t) {
    const auto tri = s.triangle(t);
    const glm::vec3 c = (tri[0] + tri[1] + tri[2]) / 3.0f;
    const glm::vec3 nn = glm::cross(tri[1] - tri[0], tri[2] - tri[0]);
    if (binary) {
      for (const float f : {c.x, c.y, c.z, nn.x, nn.y, nn.z}) append(out, f);
    } else {
      text << c.x << ' ' << c.y << ' ' << c.z << ' ' << nn.x << ' ' << nn.y << ' ' << nn.z << '\n';
    }
  }
  return out + text.str();
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: exao_fuzz_seeds OUT_FOLDER\n");
    return 2;
  }
  const fs::path out = argv[1];
  for (const std::string& name : exao::builtin_scene_names()) {
    const exao::Result<Scene> scene = exao::builtin_scene(name);
    if (!scene) {
      std::fprintf(stderr, "exao_fuzz_seeds: %s\n", scene.error().message.c_str());
      return 1;
    }
    const Scene& s = *scene;
    write(out / "gltf" / (name + ".gltf"), gltf(s));
    write(out / "gltf" / (name + ".glb"), glb(s));
    write(out / "obj" / (name + ".obj"), obj(s));
    write(out / "ply" / (name + ".ply"), ply(s, false));
    write(out / "ply" / (name + "-binary.ply"), ply(s, true));
    write(out / "off" / (name + ".off"), off(s, false));
    write(out / "off" / (name + "-colour.off"), off(s, true));
    write(out / "stl" / (name + ".stl"), stl(s, false));
    write(out / "stl" / (name + "-binary.stl"), stl(s, true));
    write(out / "points-txt" / (name + ".txt"), points_text(s));
    write(out / "points-ply" / (name + ".ply"), points_ply(s, false));
    write(out / "points-ply" / (name + "-binary.ply"), points_ply(s, true));
  }
  return 0;
}
