#include "bake/labels.h"

namespace exao::bake {

const tinygltf::Primitive& gltf_primitive(const tinygltf::Model& model, const MeshPrimitive& prim) {
  return model.meshes[static_cast<std::size_t>(prim.mesh)].primitives[static_cast<std::size_t>(prim.primitive)];
}

std::string mesh_label(const tinygltf::Model& model, int mesh) {
  const std::string& name = model.meshes[static_cast<std::size_t>(mesh)].name;
  return name.empty() ? "mesh " + std::to_string(mesh) : "mesh '" + name + "'";
}

std::string primitive_label(const tinygltf::Model& model, const MeshPrimitive& prim) {
  return mesh_label(model, prim.mesh) + " primitive " + std::to_string(prim.primitive);
}

std::string node_label(const tinygltf::Model& model, int node) {
  const std::string& name = model.nodes[static_cast<std::size_t>(node)].name;
  return name.empty() ? "node " + std::to_string(node) : "node '" + name + "'";
}

}  // namespace exao::bake
