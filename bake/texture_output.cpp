// Texture bake step 8 (bake/texture_steps.h): the maps into the model (one image, texture and
// sampler each; the image's bytes come at save), each material's occlusionTexture, and the
// generated UV sets (bake/uv_rewrite.h).

#include "bake/labels.h"
#include "bake/texture_steps.h"
#include "bake/uv_rewrite.h"

namespace exao::bake {

namespace {

// The one sampler of every AO map: linear, mipmapped, clamped.
int add_ao_sampler(tinygltf::Model& model) {
  tinygltf::Sampler sampler;
  sampler.name = "exao AO";
  sampler.magFilter = TINYGLTF_TEXTURE_FILTER_LINEAR;
  sampler.minFilter = TINYGLTF_TEXTURE_FILTER_LINEAR_MIPMAP_LINEAR;
  sampler.wrapS = sampler.wrapT = TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE;
  model.samplers.push_back(sampler);
  return static_cast<int>(model.samplers.size() - 1);
}

// The map's image (its bytes come at save; map.image is set) and texture; returns the texture.
int add_map_texture(tinygltf::Model& model, const std::string& name, AoMap& map, int sampler) {
  tinygltf::Image image;
  image.name = name + " AO" + (map.label.empty() ? "" : " " + map.label);
  image.mimeType = "image/png";
  model.images.push_back(image);
  map.image = static_cast<int>(model.images.size() - 1);
  tinygltf::Texture texture;
  texture.name = image.name;
  texture.source = map.image;
  texture.sampler = sampler;
  model.textures.push_back(texture);
  return static_cast<int>(model.textures.size() - 1);
}

// Every primitive of map `map_index`'s parts draws with `material`.
void assign_material(tinygltf::Model& model, const ModelWalk& walk, const BakeResult& result, std::size_t map_index,
                     int material) {
  for (std::size_t p = 0; p < walk.parts.size(); ++p) {
    if (result.part_map[p] != static_cast<int>(map_index)) continue;
    const MeshPrimitive& prim = walk.primitives[static_cast<std::size_t>(walk.parts[p].primitive)];
    model.meshes[static_cast<std::size_t>(prim.mesh)].primitives[static_cast<std::size_t>(prim.primitive)].material = material;
  }
}

// The material that carries map `map_index`: its own; glTF's default made explicit (single-sided,
// white) for primitives without one; a copy for generated UVs when the material also carries a
// map on file UVs.
int map_material(tinygltf::Model& model, const ModelWalk& walk, const TexturePlan& plan, std::size_t map_index,
                 BakeResult& result) {
  const AoMap& map = result.maps[map_index];
  int material = map.material;
  if (material < 0) {
    tinygltf::Material made;
    made.name = "exao default material";
    model.materials.push_back(made);
    material = static_cast<int>(model.materials.size() - 1);
    assign_material(model, walk, result, map_index, material);
    result.notes.push_back("primitives without a material got one (glTF's default) to carry the AO map");
  }
  if (plan.map_generated[map_index] && map.material >= 0 && plan.map_of_key.count({map.material, false}) != 0) {
    tinygltf::Material copy = model.materials[static_cast<std::size_t>(material)];
    copy.name += copy.name.empty() ? "exao AO UV set" : " (exao AO UV set)";
    model.materials.push_back(std::move(copy));
    material = static_cast<int>(model.materials.size() - 1);
    assign_material(model, walk, result, map_index, material);
    result.notes.push_back("material " + std::to_string(map.material) +
                           " is shared by primitives on file and generated UVs: a copy carries the generated UVs' map");
  }
  return material;
}

// The material's occlusionTexture: the map's texture, read through the UV set its primitives use
// (and the slot's KHR_texture_transform, the space the map is laid out in).
void set_occlusion_texture(tinygltf::Model& model, int material, int texture, const ModelWalk& walk,
                           const TexturePlan& plan, const BakeOptions& options, std::size_t map_index, BakeResult& result) {
  const AoMap& map = result.maps[map_index];
  const bool generated = plan.map_generated[map_index];
  tinygltf::Material& target = model.materials[static_cast<std::size_t>(material)];
  if (target.occlusionTexture.index >= 0) {
    result.notes.push_back("material " + (target.name.empty() ? std::to_string(material) : "'" + target.name + "'") +
                           " had an occlusionTexture: the baked map replaces it");
  }
  target.occlusionTexture.index = texture;
  target.occlusionTexture.strength = 1.0;
  target.occlusionTexture.extensions.erase("KHR_texture_transform");
  int set = options.uv_set;
  for (std::size_t i = 0; i < walk.primitives.size(); ++i) {
    const PrimitiveUv& u = plan.primitives[i];
    if (!u.used || u.generated != generated || walk.primitives[i].material != map.material) continue;
    if (generated) {
      set = u.set;
    } else if (u.slot.has_transform) {
      target.occlusionTexture.extensions["KHR_texture_transform"] = u.slot.transform;
    }
    break;
  }
  target.occlusionTexture.texCoord = set;
}

}  // namespace

Result<void> write_maps(tinygltf::Model& model, const std::string& name, const ModelWalk& walk,
                        const BakeOptions& options, const TexturePlan& plan, BakeResult& result) {
  const int sampler = add_ao_sampler(model);
  for (std::size_t m = 0; m < result.maps.size(); ++m) {
    const int texture = add_map_texture(model, name, result.maps[m], sampler);
    const int material = map_material(model, walk, plan, m, result);
    set_occlusion_texture(model, material, texture, walk, plan, options, m, result);
  }
  for (std::size_t i = 0; i < walk.primitives.size(); ++i) {
    const PrimitiveUv& u = plan.primitives[i];
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
