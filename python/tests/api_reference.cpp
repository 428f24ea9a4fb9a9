// The C++ API's answer for the Python module's equality test (python/tests/test_exao.py): reads
// a mesh and receivers the test wrote, builds exao::api::Engine over them and writes the masks.
//
//   python_api_reference MESH RECEIVERS OUT SAMPLES RADIUS|default FALLOFF BACKEND
//   MESH:      u64 vertex count V, u64 face count F, V x 3 float32, F x 3 uint32 (two-sided)
//   RECEIVERS: u64 count N, N x 3 float32 points, N x 3 float32 normals, N uint64 keys
//   OUT:       N x mask_words uint64 masks, receiver-major

#include <cstdint>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "exao/exao.hpp"

namespace {

template <class T>
bool read(std::ifstream& in, std::vector<T>& out, std::size_t count) {
  out.resize(count);
  return static_cast<bool>(in.read(reinterpret_cast<char*>(out.data()), static_cast<std::streamsize>(count * sizeof(T))));
}

int fail(const std::string& message) {
  std::fprintf(stderr, "python_api_reference: %s\n", message.c_str());
  return 1;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 8 && argc != 9) return fail("usage: MESH RECEIVERS OUT SAMPLES RADIUS|default FALLOFF bvh|brute|embree [OFFSET]");
  std::ifstream mesh_file(argv[1], std::ios::binary);
  std::uint64_t sizes[2] = {};
  if (!mesh_file.read(reinterpret_cast<char*>(sizes), sizeof sizes)) return fail("cannot read the mesh");
  std::vector<float> vertices;
  std::vector<std::uint32_t> faces;
  if (!read(mesh_file, vertices, sizes[0] * 3) || !read(mesh_file, faces, sizes[1] * 3)) return fail("short mesh file");

  std::ifstream receiver_file(argv[2], std::ios::binary);
  std::uint64_t n = 0;
  if (!receiver_file.read(reinterpret_cast<char*>(&n), sizeof n)) return fail("cannot read the receivers");
  std::vector<float> points, normals;
  std::vector<std::uint64_t> keys;
  if (!read(receiver_file, points, n * 3) || !read(receiver_file, normals, n * 3) || !read(receiver_file, keys, n)) {
    return fail("short receivers file");
  }

  exao::api::Mesh mesh;
  mesh.vertices = vertices.data();
  mesh.vertex_count = sizes[0];
  mesh.indices = faces.data();
  mesh.triangle_count = sizes[1];
  exao::api::Options options;
  options.samples = std::stoi(argv[4]);
  if (std::string(argv[5]) != "default") options.radius = std::stof(argv[5]);
  const std::string falloff = argv[6];
  options.falloff = falloff == "linear"      ? exao::api::Falloff::Linear
                    : falloff == "quadratic" ? exao::api::Falloff::Quadratic
                                             : exao::api::Falloff::Constant;
  // The API's default offset follows each point, the module's (the exao program's) the scene's
  // diagonal: the test gives both one offset.
  if (argc > 8) options.origin_offset = std::stof(argv[8]);
  const std::string backend = argv[7];
  options.backend = backend == "brute" ? exao::api::Backend::Brute
                    : backend == "embree" ? exao::api::Backend::Embree
                                          : exao::api::Backend::Bvh;
  auto engine = exao::api::Engine::build(mesh, options);
  if (!engine) return fail(engine.error().message);

  std::vector<exao::api::Receiver> receivers(n);
  for (std::size_t i = 0; i < n; ++i) {
    receivers[i].position = {points[3 * i], points[3 * i + 1], points[3 * i + 2]};
    receivers[i].normal = {normals[3 * i], normals[3 * i + 1], normals[3 * i + 2]};
    receivers[i].key = keys[i];
  }
  std::vector<std::uint64_t> words(n * engine->mask_words());
  if (auto ok = engine->masks(receivers, words); !ok) return fail(ok.error().message);
  std::ofstream out(argv[3], std::ios::binary);
  out.write(reinterpret_cast<const char*>(words.data()), static_cast<std::streamsize>(words.size() * sizeof(std::uint64_t)));
  return out ? 0 : fail("cannot write the masks");
}
