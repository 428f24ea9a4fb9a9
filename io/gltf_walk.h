#pragma once
// exao::gltf::walk_model: the default scene of a glTF model, read once for both the scene loader
// (io/gltf_loader.cpp) and the bake (bake/), so that `exao bake` sees the scene `exao render`
// sees: every mesh primitive decoded once (accessors, strips and fans, sidedness), every place a
// node draws it (the node tree's transforms and EXT_mesh_gpu_instancing rows, mirroring),
// cameras, and the world-space triangle soup the backends cast rays against, with the way back
// from each triangle to its primitive. Internal: it exposes tinygltf (io/gltf_model.h).

#include <tiny_gltf.h>

#include <array>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "core/error.h"
#include "core/scene.h"
#include "io/gltf_model.h"

namespace exao::gltf {

/// One triangle primitive of a mesh, in the mesh's own space.
struct MeshPrimitive {
  int mesh = -1;
  int primitive = -1;                  // index in the mesh's primitives
  std::vector<glm::dvec3> positions;   // per vertex (POSITION decoded)
  std::vector<std::uint32_t> corners;  // three vertex indices per triangle, front face CCW
  bool two_sided = false;              // the material's doubleSided (glTF's default material: one-sided)
  std::int32_t material = -1;
};

/// A node drawing a mesh, once per EXT_mesh_gpu_instancing row (row 0 without the extension).
struct MeshInstance {
  int node = -1;
  int row = 0;
  int mesh = -1;
  glm::dmat4 world{1.0};
  bool mirrored = false;  // det(world) < 0: corners are swapped to keep the front face CCW
};

/// One primitive as drawn by one instance.
struct Part {
  int instance = -1;                // index in ModelWalk::instances
  int primitive = -1;               // index in ModelWalk::primitives
  std::vector<glm::vec3> world;     // vertex positions in world space, as the scene has them
};

/// Where a scene triangle came from.
struct TriangleSource {
  std::uint32_t part = 0;
  std::uint32_t triangle = 0;  // index in the primitive's corners / 3
};

struct ModelWalk {
  std::vector<MeshPrimitive> primitives;
  std::vector<MeshInstance> instances;
  std::vector<Part> parts;
  Scene scene;                                 // the occluders, cameras, and what was skipped
  std::vector<TriangleSource> triangle_source;  // per scene triangle

  /// The corners of a part's triangle in front-face (world) order.
  [[nodiscard]] std::array<std::uint32_t, 3> corners(std::size_t part, std::size_t triangle) const {
    const Part& p = parts[part];
    const std::vector<std::uint32_t>& c = primitives[static_cast<std::size_t>(p.primitive)].corners;
    const std::uint32_t a = c[3 * triangle], b = c[3 * triangle + 1], d = c[3 * triangle + 2];
    if (instances[static_cast<std::size_t>(p.instance)].mirrored) return {a, d, b};
    return {a, b, d};
  }
};

/// Walks the default scene (else scene 0, else every root node), depth first, parents before
/// children. Points and lines are skipped and counted, a primitive without POSITION is skipped
/// with a note, trailing vertices of a triangle list are noted. Fails with a one-line error (no
/// file name: the caller adds it) on a malformed file (an index out of range, a cycle in the node
/// tree, a Draco primitive without fallback) or one with no triangle. `path`: how positions and
/// indices are read (io/gltf_model.h; Generic only to test Direct against).
[[nodiscard]] Result<ModelWalk> walk_model(const ModelBytes& source, AccessorPath path = AccessorPath::Direct);

}  // namespace exao::gltf
