#pragma once
// How the bake's messages name the parts of a glTF model: "mesh 'Name'" or "mesh 3",
// "<mesh> primitive 1", "node 'Name'" or "node 4". Internal to exao_bake (tinygltf).

#include <tiny_gltf.h>

#include <string>

#include "bake/model_walk.h"

namespace exao::bake {

/// The glTF primitive a walked primitive was read from.
[[nodiscard]] const tinygltf::Primitive& gltf_primitive(const tinygltf::Model& model, const MeshPrimitive& prim);

/// "mesh 'Name'", or "mesh 3" when it has no name.
[[nodiscard]] std::string mesh_label(const tinygltf::Model& model, int mesh);
/// The mesh's label and " primitive <index>".
[[nodiscard]] std::string primitive_label(const tinygltf::Model& model, const MeshPrimitive& prim);
/// "node 'Name'", or "node 4" when it has no name.
[[nodiscard]] std::string node_label(const tinygltf::Model& model, int node);

}  // namespace exao::bake
