#include "bake/scene_to_gltf.h"

#include <map>
#include <unordered_map>
#include <utility>

#include <glm/gtc/quaternion.hpp>

#include "bake/box_atlas.h"
#include "bake/gltf_access.h"
#include "core/position_key.h"

namespace exao::bake {
namespace {

// A camera node at the camera's pose: glTF cameras look down local -Z with +Y up.
void add_camera(tinygltf::Model& model, const Camera& camera, float diagonal) {
  tinygltf::Camera cam;
  cam.name = camera.name;
  cam.type = "perspective";
  cam.perspective.yfov = camera.yfov;
  cam.perspective.znear = std::max(1e-4, 1e-3 * static_cast<double>(diagonal));
  if (camera.aspect) cam.perspective.aspectRatio = *camera.aspect;
  model.cameras.push_back(cam);
  const glm::dvec3 f = glm::normalize(glm::dvec3(camera.forward));
  const glm::dvec3 up = glm::normalize(glm::dvec3(camera.up));
  const glm::dvec3 right = glm::normalize(glm::cross(f, up));
  const glm::dquat q = glm::quat_cast(glm::dmat3(right, glm::cross(right, f), -f));
  tinygltf::Node node;
  node.name = camera.name.empty() ? "camera" : camera.name;
  node.camera = static_cast<int>(model.cameras.size() - 1);
  node.translation = {camera.eye.x, camera.eye.y, camera.eye.z};
  node.rotation = {q.x, q.y, q.z, q.w};
  model.nodes.push_back(node);
}

}  // namespace

Result<tinygltf::Model> scene_to_gltf(const Scene& scene, const ConvertOptions& convert) {
  tinygltf::Model model;
  model.asset.version = "2.0";
  model.asset.generator = "exao bake (converted from " + (scene.name.empty() ? std::string("a triangle soup") : scene.name) + ")";
  tinygltf::Mesh mesh;
  mesh.name = scene.name;

  // Triangles grouped by (material, two-sided), in first-seen order.
  std::map<std::pair<std::int32_t, std::uint8_t>, std::vector<std::uint32_t>> groups;
  for (std::size_t t = 0; t < scene.triangle_count(); ++t) {
    groups[{scene.material[t], scene.two_sided[t]}].push_back(static_cast<std::uint32_t>(t));
  }
  for (const auto& [key, members] : groups) {
    std::vector<glm::vec3> positions;
    std::vector<std::uint32_t> indices;
    std::unordered_map<PositionKey, std::uint32_t, PositionKeyHash> weld;
    for (const std::uint32_t t : members) {
      for (int k = 0; k < 3; ++k) {
        const glm::vec3 p = scene.vertices[3 * t + static_cast<std::size_t>(k)];
        auto [it, added] = weld.emplace(position_key(p), static_cast<std::uint32_t>(positions.size()));
        if (added) positions.push_back(p);
        indices.push_back(it->second);
      }
    }
    tinygltf::Primitive prim;
    prim.mode = TINYGLTF_MODE_TRIANGLES;
    if (convert.atlas_size > 0) {
      Result<AtlasMesh> atlas = box_atlas(positions, indices, convert.atlas_size, convert.atlas_padding);
      if (!atlas) return fail(scene.name + ": " + atlas.error().message);
      std::vector<float> xyz, uv;
      xyz.reserve(atlas->source_vertex.size() * 3);
      for (std::size_t v = 0; v < atlas->source_vertex.size(); ++v) {
        const glm::vec3& p = positions[atlas->source_vertex[v]];
        xyz.insert(xyz.end(), {p.x, p.y, p.z});
        uv.insert(uv.end(), {atlas->uv[v].x, atlas->uv[v].y});
      }
      prim.attributes["POSITION"] = append_float_accessor(model, xyz, 3);
      prim.attributes["TEXCOORD_0"] = append_float_accessor(model, uv, 2);
      prim.indices = append_index_accessor(model, atlas->triangles);
    } else {
      std::vector<float> xyz;
      xyz.reserve(positions.size() * 3);
      for (const glm::vec3& p : positions) xyz.insert(xyz.end(), {p.x, p.y, p.z});
      prim.attributes["POSITION"] = append_float_accessor(model, xyz, 3);
      prim.indices = append_index_accessor(model, indices);
    }
    tinygltf::Material material;
    material.name = (key.first >= 0 ? "material " + std::to_string(key.first) : std::string("default")) +
                    (key.second ? " (two-sided)" : "");
    material.doubleSided = key.second != 0;
    material.pbrMetallicRoughness.metallicFactor = 0.0;  // glTF's default is metal; a matte white shows AO best
    model.materials.push_back(material);
    prim.material = static_cast<int>(model.materials.size() - 1);
    mesh.primitives.push_back(std::move(prim));
  }
  model.meshes.push_back(std::move(mesh));
  tinygltf::Node node;
  node.name = scene.name;
  node.mesh = 0;
  model.nodes.push_back(node);
  for (const Camera& camera : scene.cameras) add_camera(model, camera, scene.bounds().diagonal());
  tinygltf::Scene root;
  root.name = scene.name;
  for (std::size_t i = 0; i < model.nodes.size(); ++i) root.nodes.push_back(static_cast<int>(i));
  model.scenes.push_back(root);
  model.defaultScene = 0;
  // The bake's appended buffer is the model's only buffer; save() names it.
  return model;
}

}  // namespace exao::bake
