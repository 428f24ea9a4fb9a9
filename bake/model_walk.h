#pragma once
// The default scene of a glTF model as the bake sees it: core's walk (io/gltf_walk.h), the one
// the scene loader uses too, so a bake sees the scene `exao render` sees. Internal to exao_bake.

#include "io/gltf_walk.h"

namespace exao::bake {

using gltf::MeshInstance;
using gltf::MeshPrimitive;
using gltf::ModelWalk;
using gltf::Part;
using gltf::TriangleSource;
using gltf::walk_model;

}  // namespace exao::bake
