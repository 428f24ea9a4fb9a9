#include "bake/part_geometry.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "bake/gltf_access.h"
#include "bake/labels.h"

namespace exao::bake {

std::vector<std::uint32_t> part_corners(const ModelWalk& walk, std::size_t part) {
  const MeshPrimitive& prim = walk.primitives[static_cast<std::size_t>(walk.parts[part].primitive)];
  std::vector<std::uint32_t> out(prim.corners.size());
  for (std::size_t t = 0; t < prim.corners.size() / 3; ++t) {
    const auto c = walk.corners(part, t);
    std::copy(c.begin(), c.end(), out.begin() + static_cast<std::ptrdiff_t>(3 * t));
  }
  return out;
}

Result<std::vector<glm::vec3>> file_normals(const tinygltf::Model& model, const ModelWalk& walk, std::size_t part) {
  const Part& p = walk.parts[part];
  const MeshPrimitive& prim = walk.primitives[static_cast<std::size_t>(p.primitive)];
  const tinygltf::Primitive& gp = gltf_primitive(model, prim);
  const auto found = gp.attributes.find("NORMAL");
  if (found == gp.attributes.end()) return std::vector<glm::vec3>{};
  auto values = read_accessor(ModelBytes(model), found->second, 3, kNormalTypes, true, primitive_label(model, prim) + " NORMAL");
  if (!values) return std::unexpected(values.error());
  if (values->size() != 3 * prim.positions.size()) {
    return fail(primitive_label(model, prim) + ": NORMAL has a different count than POSITION");
  }
  const glm::dmat3 m = glm::transpose(glm::inverse(glm::dmat3(walk.instances[static_cast<std::size_t>(p.instance)].world)));
  std::vector<glm::vec3> out(prim.positions.size());
  for (std::size_t v = 0; v < out.size(); ++v) {
    const glm::dvec3 n = m * glm::dvec3((*values)[3 * v], (*values)[3 * v + 1], (*values)[3 * v + 2]);
    const double length = glm::length(n);
    out[v] = length > 0.0 && std::isfinite(length) ? glm::vec3(n / length) : glm::vec3(0.0f);
  }
  return out;
}

}  // namespace exao::bake
