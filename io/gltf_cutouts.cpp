#include "io/gltf_cutouts.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

#include "io/gltf_model.h"

namespace exao::gltf {
namespace {

constexpr int kNearest = TINYGLTF_TEXTURE_FILTER_NEAREST;
constexpr int kClampToEdge = TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE;
constexpr int kMirroredRepeat = TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT;

TextureWrap wrap_of(int mode) {
  return mode == kClampToEdge ? TextureWrap::Clamp : mode == kMirroredRepeat ? TextureWrap::Mirror : TextureWrap::Repeat;
}

std::uint32_t big_endian32(const std::uint8_t* p) {
  return (std::uint32_t{p[0]} << 24) | (std::uint32_t{p[1]} << 16) | (std::uint32_t{p[2]} << 8) | p[3];
}

double number(const tinygltf::Value& value, double fallback) {
  return value.IsNumber() ? value.GetNumberAsDouble() : fallback;
}

// What a cut-out material reads besides CutoutMaterial: its UV set and KHR_texture_transform.
struct MaterialUv {
  int set = 0;                  // TEXCOORD_<set>
  glm::dmat3 transform{1.0};    // uv' = transform * (u, v, 1)
};

MaterialUv uv_of(const tinygltf::TextureInfo& info) {
  MaterialUv out;
  out.set = info.texCoord;
  const auto found = info.extensions.find("KHR_texture_transform");
  if (found == info.extensions.end() || !found->second.IsObject()) return out;
  const tinygltf::Value& ext = found->second;
  glm::dvec2 offset(0.0), scale(1.0);
  const tinygltf::Value& o = ext.Get("offset");
  if (o.IsArray() && o.ArrayLen() == 2) offset = {number(o.Get(0), 0.0), number(o.Get(1), 0.0)};
  const tinygltf::Value& s = ext.Get("scale");
  if (s.IsArray() && s.ArrayLen() == 2) scale = {number(s.Get(0), 1.0), number(s.Get(1), 1.0)};
  const double rotation = number(ext.Get("rotation"), 0.0);
  if (ext.Has("texCoord") && ext.Get("texCoord").IsInt()) out.set = ext.Get("texCoord").GetNumberAsInt();
  // The extension's T * R * S, R = [cos sin; -sin cos] (column-major glm: columns listed).
  const double c = std::cos(rotation), n = std::sin(rotation);
  const glm::dmat3 t(1.0, 0.0, 0.0, 0.0, 1.0, 0.0, offset.x, offset.y, 1.0);
  const glm::dmat3 r(c, -n, 0.0, n, c, 0.0, 0.0, 0.0, 1.0);
  const glm::dmat3 sc(scale.x, 0.0, 0.0, 0.0, scale.y, 0.0, 0.0, 0.0, 1.0);
  out.transform = t * r * sc;
  return out;
}

// The textures of the cut-out materials, decoded once per (image, sampler).
class TextureReader {
 public:
  TextureReader(const tinygltf::Model& model, std::span<const std::vector<std::uint8_t>> bytes,
                std::vector<std::string>& notes, Cutouts& out)
      : model_(model), bytes_(bytes), notes_(notes), out_(out) {}

  // Index in out.textures of glTF texture `index`, or -1 (texture alpha 1) with a note.
  int texture(int index, const std::string& material) {
    if (index < 0 || static_cast<std::size_t>(index) >= model_.textures.size()) {
      notes_.push_back("material '" + material + "': baseColorTexture " + std::to_string(index) +
                       " does not exist: its cut-out reads alpha 1 there");
      return -1;
    }
    const tinygltf::Texture& texture = model_.textures[static_cast<std::size_t>(index)];
    const std::pair<int, int> key{texture.source, texture.sampler};
    if (const auto found = cache_.find(key); found != cache_.end()) return found->second;
    const int decoded = decode(texture.source, texture.sampler, material);
    cache_.emplace(key, decoded);
    return decoded;
  }

 private:
  int decode(int image, int sampler, const std::string& material) {
    const auto skip = [&](const std::string& why) {
      notes_.push_back("material '" + material + "': " + why + ": its cut-out reads alpha 1 there");
      return -1;
    };
    if (image < 0 || static_cast<std::size_t>(image) >= model_.images.size()) return skip("its texture has no image");
    const tinygltf::Image& info = model_.images[static_cast<std::size_t>(image)];
    const std::string name = "image '" + (info.uri.empty() || info.uri.rfind("data:", 0) == 0 ? std::to_string(image) : info.uri) + "'";
    const std::size_t slot = static_cast<std::size_t>(image);
    if (slot >= bytes_.size() || bytes_[slot].empty()) return skip(name + " is missing");
    const std::vector<std::uint8_t>& bytes = bytes_[slot];
    std::uint32_t width = 0, height = 0;
    if (!image_header_size(bytes, width, height)) return skip(name + " is not a PNG or JPEG image");
    if (width == 0 || height == 0) return skip(name + " declares a size of zero");
    if (std::uint64_t{width} * height > kMaxCutoutTexels) {
      return skip(name + " is " + std::to_string(width) + " x " + std::to_string(height) +
                  " texels, beyond the limit of 8192 x 8192 a cut-out decodes");
    }
    if (bytes.size() > static_cast<std::size_t>(std::numeric_limits<int>::max())) return skip(name + " is too large");
    tinygltf::Image pixels;
    std::string err, warn;
    if (!tinygltf::LoadImageData(&pixels, image, &err, &warn, 0, 0, bytes.data(), static_cast<int>(bytes.size()),
                                 nullptr) ||
        pixels.component != 4 || pixels.width <= 0 || pixels.height <= 0) {
      return skip(name + " does not decode");
    }
    auto texture = std::make_shared<AlphaTexture>();
    texture->width = pixels.width;
    texture->height = pixels.height;
    const std::size_t texels = static_cast<std::size_t>(pixels.width) * static_cast<std::size_t>(pixels.height);
    const std::size_t bytes_per = pixels.bits == 16 ? 2 : 1;
    if (pixels.image.size() < texels * 4 * bytes_per) return skip(name + " does not decode");
    texture->alpha.resize(texels);
    for (std::size_t i = 0; i < texels; ++i) {
      const unsigned char* a = pixels.image.data() + (4 * i + 3) * bytes_per;
      // 16-bit samples are stored in the machine's order by stb_image (little endian here).
      texture->alpha[i] = bytes_per == 2 ? static_cast<std::uint16_t>(a[0] | (a[1] << 8))
                                         : static_cast<std::uint16_t>(a[0] * 257);
    }
    if (sampler >= 0 && static_cast<std::size_t>(sampler) < model_.samplers.size()) {
      const tinygltf::Sampler& s = model_.samplers[static_cast<std::size_t>(sampler)];
      texture->filter = s.magFilter == kNearest ? TextureFilter::Nearest : TextureFilter::Linear;
      texture->wrap_s = wrap_of(s.wrapS);
      texture->wrap_t = wrap_of(s.wrapT);
    }
    out_.textures.push_back(std::move(texture));
    return static_cast<int>(out_.textures.size()) - 1;
  }

  const tinygltf::Model& model_;
  std::span<const std::vector<std::uint8_t>> bytes_;
  std::vector<std::string>& notes_;
  Cutouts& out_;
  std::map<std::pair<int, int>, int> cache_;
};

// A primitive's UVs (after the material's transform) and COLOR_0 alpha, per vertex; `ok` false
// when the set the material asks for is missing or does not read (the primitive is then opaque).
struct PrimitiveAttributes {
  bool ok = false;
  std::vector<glm::vec2> uv;    // empty: the material has no texture
  std::vector<float> alpha;     // empty: no COLOR_0 (alpha 1)
};

PrimitiveAttributes read_attributes(const ModelBytes& source, const MeshPrimitive& primitive, bool textured,
                                    const MaterialUv& uv, std::vector<std::string>& notes) {
  const tinygltf::Model& model = source.model;
  PrimitiveAttributes out;
  const tinygltf::Primitive& p =
      model.meshes[static_cast<std::size_t>(primitive.mesh)].primitives[static_cast<std::size_t>(primitive.primitive)];
  const std::string where = "mesh " + std::to_string(primitive.mesh) + " primitive " + std::to_string(primitive.primitive);
  const std::size_t vertices = primitive.positions.size();
  if (textured) {
    const std::string set = "TEXCOORD_" + std::to_string(uv.set);
    const auto found = p.attributes.find(set);
    if (uv.set < 0 || found == p.attributes.end()) {
      notes.push_back(where + ": its cut-out material reads " + set + ", which it does not have: its triangles are opaque");
      return out;
    }
    Result<std::vector<double>> values = read_accessor(source, found->second, 2, kTexcoordTypes, true, set);
    if (!values || values->size() < 2 * vertices) {
      notes.push_back(where + ": " + (values ? set + " has fewer elements than POSITION" : values.error().message) +
                      ": its triangles are opaque");
      return out;
    }
    out.uv.resize(vertices);
    for (std::size_t v = 0; v < vertices; ++v) {
      const glm::dvec3 t = uv.transform * glm::dvec3((*values)[2 * v], (*values)[2 * v + 1], 1.0);
      out.uv[v] = glm::vec2(t);
    }
  }
  if (const auto found = p.attributes.find("COLOR_0"); found != p.attributes.end()) {
    const int index = found->second;
    const bool rgba = index >= 0 && static_cast<std::size_t>(index) < model.accessors.size() &&
                      model.accessors[static_cast<std::size_t>(index)].type == TINYGLTF_TYPE_VEC4;
    if (rgba) {
      Result<std::vector<double>> values = read_accessor(source, index, 4, kColorTypes, true, "COLOR_0");
      if (!values || values->size() < 4 * vertices) {
        notes.push_back(where + ": " + (values ? std::string("COLOR_0 has fewer elements than POSITION") : values.error().message) +
                        ": its triangles are opaque");
        return out;
      }
      out.alpha.resize(vertices);
      for (std::size_t v = 0; v < vertices; ++v) out.alpha[v] = static_cast<float>(std::clamp((*values)[4 * v + 3], 0.0, 1.0));
    }
  }
  out.ok = true;
  return out;
}

}  // namespace

bool keep_image_bytes(tinygltf::Image*, const int index, std::string*, std::string*, int, int, const unsigned char* bytes,
                      int size, void* user) {
  auto& images = *static_cast<std::vector<std::vector<std::uint8_t>>*>(user);
  if (index < 0) return true;
  if (images.size() <= static_cast<std::size_t>(index)) images.resize(static_cast<std::size_t>(index) + 1);
  if (bytes != nullptr && size > 0) images[static_cast<std::size_t>(index)].assign(bytes, bytes + size);
  return true;
}

bool image_header_size(std::span<const std::uint8_t> b, std::uint32_t& width, std::uint32_t& height) {
  static constexpr std::uint8_t kPng[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  if (b.size() >= 24 && std::equal(kPng, kPng + 8, b.begin())) {
    if (!(b[12] == 'I' && b[13] == 'H' && b[14] == 'D' && b[15] == 'R')) return false;
    width = big_endian32(&b[16]);
    height = big_endian32(&b[20]);
    return true;
  }
  if (b.size() < 4 || b[0] != 0xFF || b[1] != 0xD8) return false;
  // JPEG: walk the marker segments to the first start-of-frame (SOF0-15 but DHT, JPG, DAC).
  std::size_t i = 2;
  while (i + 4 <= b.size()) {
    if (b[i] != 0xFF) return false;
    const std::uint8_t marker = b[i + 1];
    if (marker == 0xFF) {  // fill byte
      ++i;
      continue;
    }
    if (marker == 0xD8 || marker == 0x01 || (marker >= 0xD0 && marker <= 0xD7)) {  // no length
      i += 2;
      continue;
    }
    const std::size_t length = (std::size_t{b[i + 2]} << 8) | b[i + 3];
    if (length < 2) return false;
    if (marker >= 0xC0 && marker <= 0xCF && marker != 0xC4 && marker != 0xC8 && marker != 0xCC) {
      if (i + 9 > b.size()) return false;
      height = (std::uint32_t{b[i + 5]} << 8) | b[i + 6];
      width = (std::uint32_t{b[i + 7]} << 8) | b[i + 8];
      return true;
    }
    i += 2 + length;
  }
  return false;
}

std::shared_ptr<const Cutouts> read_cutouts(const ModelBytes& bytes, const ModelWalk& walk,
                                            std::span<const std::vector<std::uint8_t>> image_bytes,
                                            std::vector<std::string>& notes) {
  const tinygltf::Model& model = bytes.model;
  auto out = std::make_shared<Cutouts>();
  TextureReader textures(model, image_bytes, notes, *out);
  // Per glTF material: its index in out->materials (-1: OPAQUE) and its UV set.
  std::vector<int> material_of(model.materials.size(), -1);
  std::vector<MaterialUv> uv_of_material(model.materials.size());
  for (std::size_t m = 0; m < model.materials.size(); ++m) {
    const tinygltf::Material& material = model.materials[m];
    if (material.alphaMode != "MASK" && material.alphaMode != "BLEND") continue;
    CutoutMaterial cm;
    cm.name = material.name.empty() ? "material " + std::to_string(m) : material.name;
    cm.blend = material.alphaMode == "BLEND";
    const std::vector<double>& colour = material.pbrMetallicRoughness.baseColorFactor;
    cm.factor = colour.size() == 4 && std::isfinite(colour[3]) ? static_cast<float>(std::clamp(colour[3], 0.0, 1.0)) : 1.0f;
    cm.cutoff = std::isfinite(material.alphaCutoff) ? static_cast<float>(material.alphaCutoff) : 0.5f;
    cm.rule = cm.blend ? AlphaRule::Opaque : AlphaRule::Cutoff;
    const tinygltf::TextureInfo& info = material.pbrMetallicRoughness.baseColorTexture;
    if (info.index >= 0) {
      cm.texture = textures.texture(info.index, cm.name);
      uv_of_material[m] = uv_of(info);
    }
    material_of[m] = static_cast<int>(out->materials.size());
    out->materials.push_back(std::move(cm));
  }
  if (out->materials.empty()) return nullptr;

  // Every scene triangle of those materials, with its corners' attributes.
  const Scene& scene = walk.scene;
  out->of_triangle.assign(scene.triangle_count(), -1);
  std::map<int, PrimitiveAttributes> attributes;  // by primitive index in walk.primitives
  std::size_t non_finite = 0;
  for (std::size_t t = 0; t < scene.triangle_count(); ++t) {
    const std::int32_t m = scene.material[t];
    if (m < 0 || static_cast<std::size_t>(m) >= material_of.size() || material_of[static_cast<std::size_t>(m)] < 0) continue;
    const int cut = material_of[static_cast<std::size_t>(m)];
    const TriangleSource& source = walk.triangle_source[t];
    const int primitive = walk.parts[source.part].primitive;
    auto found = attributes.find(primitive);
    if (found == attributes.end()) {
      const bool textured = out->materials[static_cast<std::size_t>(cut)].texture >= 0;
      found = attributes
                  .emplace(primitive, read_attributes(bytes, walk.primitives[static_cast<std::size_t>(primitive)], textured,
                                                      uv_of_material[static_cast<std::size_t>(m)], notes))
                  .first;
    }
    const PrimitiveAttributes& a = found->second;
    if (!a.ok) continue;
    const auto corners = walk.corners(source.part, source.triangle);
    CutoutTriangle tri;
    const auto v = scene.triangle(t);
    tri.v0 = v[0], tri.v1 = v[1], tri.v2 = v[2];
    tri.material = static_cast<std::uint32_t>(cut);
    bool finite = true;
    for (int k = 0; k < 3; ++k) {
      if (!a.uv.empty()) {
        tri.uv[k] = a.uv[corners[static_cast<std::size_t>(k)]];
        finite = finite && std::isfinite(tri.uv[k].x) && std::isfinite(tri.uv[k].y);
      }
      if (!a.alpha.empty()) tri.color_alpha[k] = a.alpha[corners[static_cast<std::size_t>(k)]];
    }
    if (!finite) {
      ++non_finite;
      continue;
    }
    out->of_triangle[t] = static_cast<std::int32_t>(out->triangles.size());
    out->triangles.push_back(tri);
  }
  if (non_finite > 0) {
    notes.push_back(std::to_string(non_finite) + " cut-out triangle(s) with a NaN or infinite UV are opaque");
  }
  if (out->triangles.empty()) return nullptr;
  return out;
}

}  // namespace exao::gltf
