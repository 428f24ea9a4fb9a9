// glTF 2.0 (.gltf/.glb) reader: walks the default scene's node tree and emits world-space
// triangles, one copy per node (and per EXT_mesh_gpu_instancing row) that uses a mesh.
//
// tinygltf parses the JSON and loads the buffers, but it does not check that an accessor's
// bytes lie inside its buffer, nor that indices refer to existing vertices or nodes. Every
// such check is done here before any byte is read: a malformed file yields an error, never a
// read out of bounds.

#include <tiny_gltf.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/constants.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "core/gltf_guard.h"
#include "core/gltf_model.h"
#include "core/load_scene.h"

namespace exao {
namespace {

using namespace gltf;  // the shared reader: core/gltf_model.h

// The positions and triangle corners of one primitive, in the mesh's own space, decoded once
// and reused by every node that instances the mesh.
struct DecodedPrimitive {
  std::vector<double> positions;       // xyz per vertex
  std::vector<std::uint32_t> corners;  // three vertex indices per triangle, front face CCW
  bool two_sided = false;
  std::int32_t material = -1;
};

// Points and lines (modes 0-3) are skipped; strips and fans become triangles that keep the
// strip's orientation (glTF 2.0 section 3.7.2.1 gives these vertex orders).
Result<std::vector<DecodedPrimitive>> decode_mesh(const tinygltf::Model& model, int mesh_index,
                                                  LoadReport& report) {
  const tinygltf::Mesh& mesh = model.meshes[static_cast<std::size_t>(mesh_index)];
  std::vector<DecodedPrimitive> out;
  for (std::size_t p = 0; p < mesh.primitives.size(); ++p) {
    const tinygltf::Primitive& prim = mesh.primitives[p];
    const std::string where =
        "mesh " + std::to_string(mesh_index) + " primitive " + std::to_string(p);
    if (prim.mode >= TINYGLTF_MODE_POINTS && prim.mode <= TINYGLTF_MODE_LINE_STRIP) {
      ++report.primitives_skipped;
      continue;
    }
    if (prim.mode != TINYGLTF_MODE_TRIANGLES && prim.mode != TINYGLTF_MODE_TRIANGLE_STRIP &&
        prim.mode != TINYGLTF_MODE_TRIANGLE_FAN) {
      return fail(where + ": unknown mode " + std::to_string(prim.mode));
    }
    const auto position = prim.attributes.find("POSITION");
    if (position == prim.attributes.end()) {
      // The spec lets a primitive omit positions; viewers draw nothing for it.
      report.notes.push_back(where + " has no POSITION: skipped");
      continue;
    }
    // A Draco primitive's accessors have no bytes unless the file also ships a fallback.
    if (prim.extensions.count("KHR_draco_mesh_compression") != 0 && position->second >= 0 &&
        static_cast<std::size_t>(position->second) < model.accessors.size() &&
        model.accessors[static_cast<std::size_t>(position->second)].bufferView < 0) {
      return fail(where + ": Draco-compressed meshes are not supported");
    }

    DecodedPrimitive decoded;
    auto positions =
        read_accessor(model, position->second, 3, kPositionTypes, true, where + " POSITION");
    if (!positions) return std::unexpected(positions.error());
    decoded.positions = std::move(*positions);
    const std::size_t vertex_count = decoded.positions.size() / 3;

    std::vector<std::uint32_t> order;
    if (prim.indices >= 0) {
      auto indices = read_accessor(model, prim.indices, 1, kIndexTypes, false, where + " indices");
      if (!indices) return std::unexpected(indices.error());
      order.reserve(indices->size());
      for (const double i : *indices) {
        if (i >= static_cast<double>(vertex_count)) {
          return fail(where + ": index " + std::to_string(static_cast<std::uint64_t>(i)) +
                      " >= vertex count " + std::to_string(vertex_count));
        }
        order.push_back(static_cast<std::uint32_t>(i));
      }
    } else {
      if (vertex_count > std::numeric_limits<std::uint32_t>::max()) {
        return fail(where + ": too many vertices");
      }
      order.resize(vertex_count);
      for (std::size_t i = 0; i < vertex_count; ++i) order[i] = static_cast<std::uint32_t>(i);
    }

    const std::size_t n = order.size();
    std::vector<std::uint32_t>& c = decoded.corners;
    if (prim.mode == TINYGLTF_MODE_TRIANGLES) {
      if (n % 3 != 0) {
        report.notes.push_back(where + ": " + std::to_string(n % 3) + " trailing vertices ignored");
      }
      c.assign(order.begin(), order.begin() + static_cast<std::ptrdiff_t>(n - n % 3));
    } else if (n >= 3) {
      c.reserve(3 * (n - 2));
      for (std::size_t i = 0; i + 2 < n; ++i) {
        if (prim.mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
          // Every other triangle swaps its last two corners so all keep the first's winding.
          const std::size_t odd = i % 2;
          c.insert(c.end(), {order[i], order[i + 1 + odd], order[i + 2 - odd]});
        } else {
          c.insert(c.end(), {order[i + 1], order[i + 2], order[0]});
        }
      }
    }

    if (prim.material >= 0) {
      if (static_cast<std::size_t>(prim.material) >= model.materials.size()) {
        return fail(where + " refers to material " + std::to_string(prim.material) + ", file has " +
                    std::to_string(model.materials.size()));
      }
      decoded.material = prim.material;
      decoded.two_sided = model.materials[static_cast<std::size_t>(prim.material)].doubleSided;
    }
    // Without a material the glTF default material applies, and it is single-sided.
    out.push_back(std::move(decoded));
  }
  return out;
}


void emit(const DecodedPrimitive& prim, const glm::dmat4& world, Scene& scene) {
  // A mirroring transform turns counter-clockwise into clockwise; swapping two corners keeps
  // the front face counter-clockwise in world space (glTF 2.0 section 3.7.4).
  const bool mirrored = glm::determinant(world) < 0.0;
  const std::size_t vertex_count = prim.positions.size() / 3;
  std::vector<glm::vec3> world_positions(vertex_count);
  for (std::size_t v = 0; v < vertex_count; ++v) {
    world_positions[v] = glm::vec3(world * glm::dvec4(glm::make_vec3(&prim.positions[3 * v]), 1.0));
  }
  for (std::size_t t = 0; t + 2 < prim.corners.size(); t += 3) {
    const glm::vec3& a = world_positions[prim.corners[t]];
    const glm::vec3& b = world_positions[prim.corners[t + 1]];
    const glm::vec3& c = world_positions[prim.corners[t + 2]];
    if (mirrored) {
      scene.add_triangle(a, c, b, prim.two_sided, prim.material);
    } else {
      scene.add_triangle(a, b, c, prim.two_sided, prim.material);
    }
  }
}


Result<Scene> build_scene(const tinygltf::Model& model) {
  if (auto ok = check_required_extensions(model); !ok) return std::unexpected(ok.error());
  auto roots = root_nodes(model);
  if (!roots) return std::unexpected(roots.error());

  Scene scene;
  std::map<int, std::vector<DecodedPrimitive>> meshes;  // decoded on first use
  std::size_t skinned = 0;
  // Depth-first, parents before children, children in file order; explicit stack so a deep
  // (or hostile) hierarchy cannot overflow the call stack.
  struct Visit {
    int node;
    glm::dmat4 parent;
  };
  std::vector<Visit> stack;
  for (auto it = roots->rbegin(); it != roots->rend(); ++it) {
    stack.push_back({*it, glm::dmat4(1.0)});
  }
  std::vector<bool> visited(model.nodes.size(), false);
  while (!stack.empty()) {
    const Visit visit = stack.back();
    stack.pop_back();
    if (visit.node < 0 || static_cast<std::size_t>(visit.node) >= model.nodes.size()) {
      return fail("scene refers to node " + std::to_string(visit.node) + ", file has " +
                  std::to_string(model.nodes.size()));
    }
    const auto index = static_cast<std::size_t>(visit.node);
    // glTF node hierarchies are strict trees; a node reached twice means a cycle.
    if (visited[index]) {
      return fail("node " + std::to_string(visit.node) + " is reached twice in the node tree");
    }
    visited[index] = true;
    const tinygltf::Node& node = model.nodes[index];
    auto local = local_transform(node, visit.node);
    if (!local) return std::unexpected(local.error());
    const glm::dmat4 world = visit.parent * *local;

    if (node.camera >= 0) {
      if (static_cast<std::size_t>(node.camera) >= model.cameras.size()) {
        return fail("node " + std::to_string(visit.node) + " refers to camera " +
                    std::to_string(node.camera) + ", file has " +
                    std::to_string(model.cameras.size()));
      }
      add_camera(model, node, world, scene);
    }
    if (node.mesh >= 0) {
      if (static_cast<std::size_t>(node.mesh) >= model.meshes.size()) {
        return fail("node " + std::to_string(visit.node) + " refers to mesh " +
                    std::to_string(node.mesh) + ", file has " +
                    std::to_string(model.meshes.size()));
      }
      auto found = meshes.find(node.mesh);
      if (found == meshes.end()) {
        auto decoded = decode_mesh(model, node.mesh, scene.report);
        if (!decoded) return std::unexpected(decoded.error());
        found = meshes.emplace(node.mesh, std::move(*decoded)).first;
      }
      auto instances = instance_transforms(model, node, visit.node);
      if (!instances) return std::unexpected(instances.error());
      if (node.skin >= 0) ++skinned;
      for (const glm::dmat4& instance : *instances) {
        for (const DecodedPrimitive& prim : found->second) emit(prim, world * instance, scene);
      }
    }
    for (auto it = node.children.rbegin(); it != node.children.rend(); ++it) {
      stack.push_back({*it, world});
    }
  }

  if (scene.report.primitives_skipped > 0) {
    scene.report.notes.push_back(std::to_string(scene.report.primitives_skipped) +
                                 " point/line primitive uses skipped (AO needs triangles)");
  }
  if (skinned > 0) {
    scene.report.notes.push_back(
        std::to_string(skinned) +
        " skinned mesh node(s) drawn in their bind pose (skinning is not applied)");
  }
  if (scene.triangle_count() == 0) return fail("no triangles");
  return scene;
}

// AO needs no texture: images are neither decoded nor required to exist.
bool ignore_image(tinygltf::Image*, const int, std::string*, std::string*, int, int,
                  const unsigned char*, int, void*) {
  return true;
}

bool starts_with_glb_magic(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::array<char, 4> magic{};
  in.read(magic.data(), magic.size());
  return in.gcount() == 4 && std::memcmp(magic.data(), "glTF", 4) == 0;
}

Result<Scene> load(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return fail("no such file");
  if (auto ok = check_json_depth(path); !ok) return std::unexpected(ok.error());
  tinygltf::TinyGLTF context;
  install_safe_file_access(context);
  context.SetImageLoader(&ignore_image, nullptr);
  tinygltf::Model model;
  std::string err;
  std::string warn;
  // The container is told by its magic, not its name, so a mislabelled file still loads.
  const bool binary = starts_with_glb_magic(path);
  const bool ok = binary ? context.LoadBinaryFromFile(&model, &err, &warn, path)
                         : context.LoadASCIIFromFile(&model, &err, &warn, path);
  if (!ok) return fail(one_line(err));
  return build_scene(model);
}

}  // namespace

Result<Scene> load_gltf(const std::string& path) {
  Result<Scene> scene;
  // tinygltf and the standard library may throw (bad_alloc on a hostile count, json errors);
  // no exception leaves the loader.
  try {
    scene = load(path);
  } catch (const std::exception& e) {
    scene = fail(one_line(e.what()));
  } catch (...) {
    scene = fail("unknown error while reading glTF");
  }
  if (!scene) return fail(path + ": " + scene.error().message);
  scene->name = std::filesystem::path(path).stem().string();
  return scene;
}

}  // namespace exao
