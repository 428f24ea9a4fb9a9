#include "io/gltf_walk.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <string>

#include <glm/gtc/type_ptr.hpp>

#include "core/huge_pages.h"
#include "io/gltf_model.h"

namespace exao::gltf {
namespace {

// The vertex order of a primitive's triangles: its indices, or 0..count-1 without them.
Result<std::vector<std::uint32_t>> vertex_order(const ModelBytes& source, const tinygltf::Primitive& prim,
                                                std::size_t vertex_count, const std::string& where, AccessorPath path) {
  if (prim.indices >= 0) return read_indices(source, prim.indices, vertex_count, where, path);
  if (vertex_count > std::numeric_limits<std::uint32_t>::max()) return fail(where + ": too many vertices");
  std::vector<std::uint32_t> order(vertex_count);
  for (std::size_t i = 0; i < vertex_count; ++i) order[i] = static_cast<std::uint32_t>(i);
  return order;
}

// Triangles from a list, strip or fan; strips and fans keep the first triangle's winding (glTF
// 2.0 section 3.7.2.1 gives these vertex orders).
std::vector<std::uint32_t> triangle_corners(int mode, std::vector<std::uint32_t> order, const std::string& where,
                                            LoadReport& report) {
  const std::size_t n = order.size();
  if (mode == TINYGLTF_MODE_TRIANGLES) {
    if (n % 3 != 0) report.notes.push_back(where + ": " + std::to_string(n % 3) + " trailing vertices ignored");
    order.resize(n - n % 3);
    return order;
  }
  std::vector<std::uint32_t> c;
  if (n < 3) return c;
  c.reserve(3 * (n - 2));
  for (std::size_t i = 0; i + 2 < n; ++i) {
    if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
      const std::size_t odd = i % 2;  // every other triangle swaps two corners to keep the winding
      c.insert(c.end(), {order[i], order[i + 1 + odd], order[i + 2 - odd]});
    } else {
      c.insert(c.end(), {order[i + 1], order[i + 2], order[0]});
    }
  }
  return c;
}

// The triangle primitives of a mesh; points, lines and primitives without POSITION are skipped.
Result<std::vector<MeshPrimitive>> decode_mesh(const ModelBytes& source, int mesh_index, LoadReport& report,
                                               AccessorPath path) {
  const tinygltf::Model& model = source.model;
  const tinygltf::Mesh& mesh = model.meshes[static_cast<std::size_t>(mesh_index)];
  std::vector<MeshPrimitive> out;
  for (std::size_t p = 0; p < mesh.primitives.size(); ++p) {
    const tinygltf::Primitive& prim = mesh.primitives[p];
    const std::string where = "mesh " + std::to_string(mesh_index) + " primitive " + std::to_string(p);
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
    MeshPrimitive decoded;
    decoded.mesh = mesh_index;
    decoded.primitive = static_cast<int>(p);
    auto positions = read_vec3(source, position->second, kPositionTypes, true, where + " POSITION", path);
    if (!positions) return std::unexpected(positions.error());
    decoded.positions = std::move(*positions);
    auto order = vertex_order(source, prim, decoded.positions.size(), where, path);
    if (!order) return std::unexpected(order.error());
    decoded.corners = triangle_corners(prim.mode, std::move(*order), where, report);
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

// One part's triangles into the scene: a mirroring transform swaps two corners so the front
// face stays counter-clockwise in world space (glTF 2.0 section 3.7.4).
void emit(ModelWalk& walk, std::size_t part_index) {
  Part& part = walk.parts[part_index];
  const MeshInstance& instance = walk.instances[static_cast<std::size_t>(part.instance)];
  const MeshPrimitive& prim = walk.primitives[static_cast<std::size_t>(part.primitive)];
  reserve_huge(part.world, prim.positions.size());
  part.world.resize(prim.positions.size());
  for (std::size_t v = 0; v < prim.positions.size(); ++v) {
    part.world[v] = glm::vec3(instance.world * glm::dvec4(prim.positions[v], 1.0));
  }
  for (std::size_t t = 0; t + 2 < prim.corners.size(); t += 3) {
    const auto c = walk.corners(part_index, t / 3);
    if (walk.scene.add_triangle(part.world[c[0]], part.world[c[1]], part.world[c[2]], prim.two_sided, prim.material)) {
      walk.triangle_source.push_back({static_cast<std::uint32_t>(part_index), static_cast<std::uint32_t>(t / 3)});
    }
  }
}

// The node's mesh, placed once per instancing row (its parts are emitted after the walk); its
// primitives decoded on first use.
Result<void> draw_mesh(const ModelBytes& source, const tinygltf::Node& node, int node_index, const glm::dmat4& world,
                       std::map<int, std::vector<int>>& decoded, ModelWalk& walk, AccessorPath path) {
  const tinygltf::Model& model = source.model;
  if (static_cast<std::size_t>(node.mesh) >= model.meshes.size()) {
    return fail("node " + std::to_string(node_index) + " refers to mesh " + std::to_string(node.mesh) + ", file has " +
                std::to_string(model.meshes.size()));
  }
  auto found = decoded.find(node.mesh);
  if (found == decoded.end()) {
    auto primitives = decode_mesh(source, node.mesh, walk.scene.report, path);
    if (!primitives) return std::unexpected(primitives.error());
    std::vector<int> indices;
    for (MeshPrimitive& prim : *primitives) {
      indices.push_back(static_cast<int>(walk.primitives.size()));
      walk.primitives.push_back(std::move(prim));
    }
    found = decoded.emplace(node.mesh, std::move(indices)).first;
  }
  auto rows = instance_transforms(source, node, node_index);
  if (!rows) return std::unexpected(rows.error());
  for (std::size_t r = 0; r < rows->size(); ++r) {
    MeshInstance instance;
    instance.node = node_index;
    instance.row = static_cast<int>(r);
    instance.mesh = node.mesh;
    instance.world = world * (*rows)[r];
    instance.mirrored = glm::determinant(instance.world) < 0.0;
    walk.instances.push_back(instance);
    for (const int prim : found->second) walk.parts.push_back({static_cast<int>(walk.instances.size() - 1), prim, {}});
  }
  return {};
}

}  // namespace

Result<ModelWalk> walk_model(const ModelBytes& source, AccessorPath path) {
  const tinygltf::Model& model = source.model;
  if (auto ok = check_required_extensions(model); !ok) return std::unexpected(ok.error());
  auto roots = root_nodes(model);
  if (!roots) return std::unexpected(roots.error());

  ModelWalk walk;
  std::map<int, std::vector<int>> decoded;  // mesh -> its primitives' indices in walk.primitives
  std::size_t skinned = 0;
  // Depth-first, parents before children, children in file order; an explicit stack so that a
  // deep (or hostile) hierarchy cannot overflow the call stack.
  struct Visit {
    int node;
    glm::dmat4 parent;
  };
  std::vector<Visit> stack;
  for (auto it = roots->rbegin(); it != roots->rend(); ++it) stack.push_back({*it, glm::dmat4(1.0)});
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
    if (visited[index]) return fail("node " + std::to_string(visit.node) + " is reached twice in the node tree");
    visited[index] = true;
    const tinygltf::Node& node = model.nodes[index];
    auto local = local_transform(node, visit.node);
    if (!local) return std::unexpected(local.error());
    const glm::dmat4 world = visit.parent * *local;
    if (node.camera >= 0) {
      if (static_cast<std::size_t>(node.camera) >= model.cameras.size()) {
        return fail("node " + std::to_string(visit.node) + " refers to camera " + std::to_string(node.camera) +
                    ", file has " + std::to_string(model.cameras.size()));
      }
      add_camera(model, node, world, walk.scene);
    }
    if (node.mesh >= 0) {
      if (auto ok = draw_mesh(source, node, visit.node, world, decoded, walk, path); !ok) return std::unexpected(ok.error());
      if (node.skin >= 0) ++skinned;
    }
    for (auto it = node.children.rbegin(); it != node.children.rend(); ++it) stack.push_back({*it, world});
  }
  // The triangles, in the order the walk placed the parts, into arrays sized once (with the
  // padding that lets Embree read the vertices in place, core/scene.h).
  std::size_t triangles = 0;
  for (const Part& part : walk.parts) triangles += walk.primitives[static_cast<std::size_t>(part.primitive)].corners.size() / 3;
  walk.scene.reserve(triangles);
  reserve_huge(walk.triangle_source, triangles);
  for (std::size_t p = 0; p < walk.parts.size(); ++p) emit(walk, p);
  LoadReport& report = walk.scene.report;
  if (report.primitives_skipped > 0) {
    report.notes.push_back(std::to_string(report.primitives_skipped) +
                           " point/line primitive uses skipped (AO needs triangles)");
  }
  if (skinned > 0) {
    report.notes.push_back(std::to_string(skinned) +
                           " skinned mesh node(s) in their bind pose (skinning is not applied)");
  }
  if (walk.scene.triangle_count() == 0) return fail("no triangles");
  for (const tinygltf::Material& material : model.materials) {
    const std::vector<double>& colour = material.pbrMetallicRoughness.baseColorFactor;
    const double alpha = colour.size() == 4 && std::isfinite(colour[3]) ? std::clamp(colour[3], 0.0, 1.0) : 1.0;
    const double opacity = material.alphaMode == "BLEND" ? alpha
                           : material.alphaMode == "MASK" ? (alpha >= material.alphaCutoff ? 1.0 : 0.0)
                                                          : 1.0;
    walk.scene.material_opacity.push_back(static_cast<float>(opacity));
  }
  return walk;
}

}  // namespace exao::gltf
