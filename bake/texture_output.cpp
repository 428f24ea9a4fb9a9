// Texture bake step 8 (bake/texture_steps.h): the maps into the model (one image, texture and
// sampler each; the image's bytes come at save), each material's occlusionTexture, and the
// generated UV sets (bake/uv_rewrite.h).

#include "bake/labels.h"
#include "bake/texture_steps.h"
#include "bake/uv_rewrite.h"

namespace exao::bake {

Result<void> write_maps(tinygltf::Model& model, const std::string& name, const ModelWalk& walk,
                        const BakeOptions& options, const TexturePlan& plan, BakeResult& result) {
  const std::vector<PrimitiveUv>& prim_uv = plan.primitives;
  const std::map<std::pair<int, bool>, int>& map_of_key = plan.map_of_key;
  const std::vector<bool>& map_generated = plan.map_generated;
  // The maps into the model: one image, texture and sampler each; the image's bytes come at save.
  tinygltf::Sampler sampler;
  sampler.name = "exao AO";
  sampler.magFilter = TINYGLTF_TEXTURE_FILTER_LINEAR;
  sampler.minFilter = TINYGLTF_TEXTURE_FILTER_LINEAR_MIPMAP_LINEAR;
  sampler.wrapS = sampler.wrapT = TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE;
  model.samplers.push_back(sampler);
  const int sampler_index = static_cast<int>(model.samplers.size() - 1);
  for (AoMap& map : result.maps) {
    tinygltf::Image image;
    image.name = name + " AO" + (map.label.empty() ? "" : " " + map.label);
    image.mimeType = "image/png";
    model.images.push_back(image);
    map.image = static_cast<int>(model.images.size() - 1);
    tinygltf::Texture texture;
    texture.name = image.name;
    texture.source = map.image;
    texture.sampler = sampler_index;
    model.textures.push_back(texture);
    const int texture_index = static_cast<int>(model.textures.size() - 1);
    int material = map.material;
    if (material < 0) {
      // glTF's default material, made explicit so that it can carry the map: single-sided, white.
      tinygltf::Material made;
      made.name = "exao default material";
      model.materials.push_back(made);
      material = static_cast<int>(model.materials.size() - 1);
      for (std::size_t p = 0; p < walk.parts.size(); ++p) {
        if (result.part_map[p] != &map - result.maps.data()) continue;
        const MeshPrimitive& prim = walk.primitives[static_cast<std::size_t>(walk.parts[p].primitive)];
        model.meshes[static_cast<std::size_t>(prim.mesh)].primitives[static_cast<std::size_t>(prim.primitive)].material = material;
      }
      result.notes.push_back("primitives without a material got one (glTF's default) to carry the AO map");
    }
    const std::size_t map_index = static_cast<std::size_t>(&map - result.maps.data());
    const bool generated = map_generated[map_index];
    if (generated && map.material >= 0 && map_of_key.count({map.material, false}) != 0) {
      // The material also carries a map on file UVs: the generated primitives get a copy.
      tinygltf::Material copy = model.materials[static_cast<std::size_t>(material)];
      copy.name += copy.name.empty() ? "exao AO UV set" : " (exao AO UV set)";
      model.materials.push_back(std::move(copy));
      material = static_cast<int>(model.materials.size() - 1);
      for (std::size_t p = 0; p < walk.parts.size(); ++p) {
        if (result.part_map[p] != static_cast<int>(map_index)) continue;
        const MeshPrimitive& prim = walk.primitives[static_cast<std::size_t>(walk.parts[p].primitive)];
        model.meshes[static_cast<std::size_t>(prim.mesh)].primitives[static_cast<std::size_t>(prim.primitive)].material = material;
      }
      result.notes.push_back("material " + std::to_string(map.material) +
                             " is shared by primitives on file and generated UVs: a copy carries the generated UVs' map");
    }
    tinygltf::Material& target = model.materials[static_cast<std::size_t>(material)];
    if (target.occlusionTexture.index >= 0) {
      result.notes.push_back("material " + (target.name.empty() ? std::to_string(material) : "'" + target.name + "'") +
                             " had an occlusionTexture: the baked map replaces it");
    }
    target.occlusionTexture.index = texture_index;
    target.occlusionTexture.strength = 1.0;
    target.occlusionTexture.extensions.erase("KHR_texture_transform");
    int set = options.uv_set;
    for (std::size_t i = 0; i < walk.primitives.size(); ++i) {
      const PrimitiveUv& u = prim_uv[i];
      if (!u.used || u.generated != generated || walk.primitives[i].material != map.material) continue;
      if (generated) {
        set = u.set;
      } else if (u.slot.has_transform) {
        // The map is laid out in the slot's transformed space, so it reads through the same transform.
        target.occlusionTexture.extensions["KHR_texture_transform"] = u.slot.transform;
      }
      break;
    }
    target.occlusionTexture.texCoord = set;
  }
  for (std::size_t i = 0; i < walk.primitives.size(); ++i) {
    const PrimitiveUv& u = prim_uv[i];
    if (!u.used || !u.generated) continue;
    const MeshPrimitive& prim = walk.primitives[i];
    if (auto ok = write_generated_uvs(model, prim.mesh, prim.primitive, u.source, u.vertex_uv, u.corners, u.set,
                                      primitive_label(model, prim));
        !ok) {
      return std::unexpected(ok.error());
    }
  }
  return {};
}

}  // namespace exao::bake
