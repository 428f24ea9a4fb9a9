#pragma once
// Vertex AO into the glTF model: one new float accessor per primitive, COLOR_0 (an existing one
// multiplied) or _AO, and meshes split per node where the nodes' AO differs. Internal to
// exao_bake (tinygltf).

#include <tiny_gltf.h>

#include <span>
#include <string>
#include <vector>

#include "bake/options.h"
#include "bake/model_walk.h"
#include "core/error.h"

namespace exao::bake {

/// `part_vertex_ao[p]`: AO per vertex of walk.parts[p]. Nodes that draw a mesh with identical AO
/// share it; every other node gets a copy of the mesh (same accessors, its own AO accessor). A
/// node with EXT_mesh_gpu_instancing rows gets their mean. Returns the number of meshes added;
/// appends one line per notable change to `notes`. Fails on an unreadable COLOR_0.
[[nodiscard]] Result<std::size_t> write_vertex_ao(tinygltf::Model& model, const ModelWalk& walk,
                                                  std::span<const std::vector<float>> part_vertex_ao,
                                                  VertexChannel channel, std::vector<std::string>& notes);

}  // namespace exao::bake
