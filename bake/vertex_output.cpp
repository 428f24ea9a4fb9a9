#include "bake/vertex_output.h"

#include <algorithm>
#include <map>

#include "bake/gltf_access.h"
#include "bake/labels.h"

namespace exao::bake {
namespace {

// A node's AO for each of its mesh's triangle primitives, keyed by index in walk.primitives.
using NodeAo = std::map<int, std::vector<float>>;

Result<int> ao_accessor(tinygltf::Model& model, const tinygltf::Primitive& prim, const std::vector<float>& ao,
                        VertexChannel channel, const std::string& where, bool& multiplied) {
  if (channel == VertexChannel::Attribute) return append_float_accessor(model, ao, 1);
  const auto color = prim.attributes.find("COLOR_0");
  if (color == prim.attributes.end()) {
    std::vector<float> rgb(ao.size() * 3);
    for (std::size_t v = 0; v < ao.size(); ++v) rgb[3 * v] = rgb[3 * v + 1] = rgb[3 * v + 2] = ao[v];
    return append_float_accessor(model, rgb, 3);
  }
  // An existing colour is kept and darkened: RGB times AO, alpha as it was.
  const int components = accessor_components(model, color->second);
  if (components != 3 && components != 4) return fail(where + " COLOR_0 is neither VEC3 nor VEC4");
  auto values = read_accessor(ModelBytes(model), color->second, components, kColorTypes, true, where + " COLOR_0");
  if (!values) return std::unexpected(values.error());
  const auto n = static_cast<std::size_t>(components);
  if (values->size() / n != ao.size()) return fail(where + " COLOR_0 has a different count than POSITION");
  std::vector<float> out(values->size());
  for (std::size_t v = 0; v < ao.size(); ++v) {
    for (std::size_t c = 0; c < n; ++c) {
      const double x = (*values)[v * n + c];
      out[v * n + c] = static_cast<float>(c < 3 ? x * static_cast<double>(ao[v]) : x);
    }
  }
  multiplied = true;
  return append_float_accessor(model, out, components);
}

// Per node, the mean AO over its instancing rows (a note for each node instanced), in the order
// the nodes first appear among the walk's parts.
struct NodeAos {
  std::map<int, NodeAo> ao;
  std::vector<int> order;
};

NodeAos node_means(const tinygltf::Model& model, const ModelWalk& walk, std::span<const std::vector<float>> part_vertex_ao,
                   std::vector<std::string>& notes) {
  NodeAos nodes;
  std::map<int, int> node_rows;
  for (std::size_t p = 0; p < walk.parts.size(); ++p) {
    const MeshInstance& instance = walk.instances[static_cast<std::size_t>(walk.parts[p].instance)];
    auto [it, added] = nodes.ao.try_emplace(instance.node);
    if (added) nodes.order.push_back(instance.node);
    std::vector<float>& sum = it->second[walk.parts[p].primitive];
    const std::vector<float>& ao = part_vertex_ao[p];
    if (sum.empty()) sum.assign(ao.size(), 0.0f);
    for (std::size_t v = 0; v < ao.size(); ++v) sum[v] += ao[v];
    node_rows[instance.node] = std::max(node_rows[instance.node], instance.row + 1);
  }
  for (auto& [node, per_primitive] : nodes.ao) {
    const int rows = node_rows[node];
    if (rows <= 1) continue;
    for (auto& [prim, sum] : per_primitive) {
      for (float& v : sum) v /= static_cast<float>(rows);
    }
    const tinygltf::Node& n = model.nodes[static_cast<std::size_t>(node)];
    notes.push_back("node " + (n.name.empty() ? std::to_string(node) : "'" + n.name + "'") + " draws " +
                    mesh_label(model, n.mesh) + " " + std::to_string(rows) +
                    " times (EXT_mesh_gpu_instancing): its vertices hold the mean AO of the instances");
  }
  return nodes;
}

// Per mesh, its nodes grouped by identical AO (the first group keeps the mesh), meshes in the
// order their nodes first appear.
struct MeshGroups {
  std::map<int, std::vector<std::vector<int>>> groups;
  std::vector<int> order;
};

MeshGroups group_by_ao(const tinygltf::Model& model, NodeAos& nodes) {
  MeshGroups out;
  for (const int node : nodes.order) {
    const int mesh = model.nodes[static_cast<std::size_t>(node)].mesh;
    auto [it, added] = out.groups.try_emplace(mesh);
    if (added) out.order.push_back(mesh);
    bool placed = false;
    for (std::vector<int>& group : it->second) {
      if (nodes.ao[group.front()] == nodes.ao[node]) {
        group.push_back(node);
        placed = true;
        break;
      }
    }
    if (!placed) it->second.push_back({node});
  }
  return out;
}

// One mesh's AO: the first group's into the mesh, each other group's into a copy that its nodes
// then draw. Returns the meshes added.
Result<std::size_t> write_mesh_ao(tinygltf::Model& model, const ModelWalk& walk, int mesh,
                                  const std::vector<std::vector<int>>& mesh_groups, NodeAos& nodes,
                                  VertexChannel channel, std::vector<std::string>& notes) {
  std::size_t nodes_drawing = 0;
  for (const auto& g : mesh_groups) nodes_drawing += g.size();
  if (mesh_groups.size() > 1) {
    notes.push_back(mesh_label(model, mesh) + " is drawn by " + std::to_string(nodes_drawing) +
                    " nodes with different AO: split into " + std::to_string(mesh_groups.size()) + " meshes");
  }
  std::size_t added_meshes = 0;
  bool multiplied = false;
  bool replaced = false;
  // Copies and colours come from the mesh as it was, before any group wrote to it.
  const tinygltf::Mesh original = model.meshes[static_cast<std::size_t>(mesh)];
  for (std::size_t g = 0; g < mesh_groups.size(); ++g) {
    int target = mesh;
    if (g > 0) {
      tinygltf::Mesh copy = original;
      const int first = mesh_groups[g].front();
      const std::string& node_name = model.nodes[static_cast<std::size_t>(first)].name;
      copy.name = (copy.name.empty() ? "mesh " + std::to_string(mesh) : copy.name) + " (AO of node " +
                  (node_name.empty() ? std::to_string(first) : node_name) + ")";
      model.meshes.push_back(std::move(copy));
      target = static_cast<int>(model.meshes.size() - 1);
      ++added_meshes;
      for (const int node : mesh_groups[g]) model.nodes[static_cast<std::size_t>(node)].mesh = target;
    }
    for (const auto& [walk_prim, ao] : nodes.ao[mesh_groups[g].front()]) {
      const int p = walk.primitives[static_cast<std::size_t>(walk_prim)].primitive;
      const tinygltf::Primitive& before = original.primitives[static_cast<std::size_t>(p)];
      const std::string where = mesh_label(model, mesh) + " primitive " + std::to_string(p);
      auto accessor = ao_accessor(model, before, ao, channel, where, multiplied);
      if (!accessor) return std::unexpected(accessor.error());
      const std::string name = channel == VertexChannel::Attribute ? "_AO" : "COLOR_0";
      if (channel == VertexChannel::Attribute && before.attributes.count(name) != 0) replaced = true;
      model.meshes[static_cast<std::size_t>(target)].primitives[static_cast<std::size_t>(p)].attributes[name] = *accessor;
    }
  }
  if (multiplied) notes.push_back(mesh_label(model, mesh) + " had COLOR_0: it was multiplied by the AO");
  if (replaced) notes.push_back(mesh_label(model, mesh) + " had an _AO attribute: it was replaced");
  return added_meshes;
}

}  // namespace

Result<std::size_t> write_vertex_ao(tinygltf::Model& model, const ModelWalk& walk,
                                    std::span<const std::vector<float>> part_vertex_ao, VertexChannel channel,
                                    std::vector<std::string>& notes) {
  NodeAos nodes = node_means(model, walk, part_vertex_ao, notes);
  MeshGroups meshes = group_by_ao(model, nodes);
  std::size_t added_meshes = 0;
  for (const int mesh : meshes.order) {
    Result<std::size_t> added = write_mesh_ao(model, walk, mesh, meshes.groups[mesh], nodes, channel, notes);
    if (!added) return std::unexpected(added.error());
    added_meshes += *added;
  }
  return added_meshes;
}

}  // namespace exao::bake
