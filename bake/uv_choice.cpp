#include "bake/uv_choice.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <vector>

namespace exao::bake {
namespace {

constexpr const char* kTransform = "KHR_texture_transform";

double number(const tinygltf::Value& v, double fallback) { return v.IsNumber() ? v.GetNumberAsDouble() : fallback; }

glm::dvec2 pair(const tinygltf::Value& object, const char* key, glm::dvec2 fallback) {
  if (!object.Has(key)) return fallback;
  const tinygltf::Value& v = object.Get(key);
  if (!v.IsArray() || v.ArrayLen() != 2) return fallback;
  return {number(v.Get(0), fallback.x), number(v.Get(1), fallback.y)};
}

// KHR_texture_transform: uv' = T * R * S * (u, v, 1), R = mat3(cos, sin, 0, -sin, cos, 0, 0, 0, 1)
// column by column, as the extension's specification writes it in GLSL.
glm::dmat3 transform_matrix(const tinygltf::Value& ext) {
  const glm::dvec2 offset = pair(ext, "offset", glm::dvec2(0.0));
  const glm::dvec2 scale = pair(ext, "scale", glm::dvec2(1.0));
  const double rotation = ext.Has("rotation") ? number(ext.Get("rotation"), 0.0) : 0.0;
  const glm::dmat3 t(1, 0, 0, 0, 1, 0, offset.x, offset.y, 1);
  const glm::dmat3 r(std::cos(rotation), std::sin(rotation), 0, -std::sin(rotation), std::cos(rotation), 0, 0, 0, 1);
  const glm::dmat3 s(scale.x, 0, 0, 0, scale.y, 0, 0, 0, 1);
  return t * r * s;
}

}  // namespace

AoSlot ao_slot(const tinygltf::Model& model, int material, int uv_set) {
  AoSlot slot;
  slot.tex_coord = slot.set = uv_set;
  if (material < 0 || static_cast<std::size_t>(material) >= model.materials.size()) return slot;
  const tinygltf::Material& m = model.materials[static_cast<std::size_t>(material)];
  struct Candidate {
    const char* name;
    int index, tex_coord;
    const tinygltf::ExtensionMap* extensions;
  };
  const Candidate candidates[] = {
      {"occlusionTexture", m.occlusionTexture.index, m.occlusionTexture.texCoord, &m.occlusionTexture.extensions},
      {"metallicRoughnessTexture", m.pbrMetallicRoughness.metallicRoughnessTexture.index,
       m.pbrMetallicRoughness.metallicRoughnessTexture.texCoord, &m.pbrMetallicRoughness.metallicRoughnessTexture.extensions},
      {"baseColorTexture", m.pbrMetallicRoughness.baseColorTexture.index, m.pbrMetallicRoughness.baseColorTexture.texCoord,
       &m.pbrMetallicRoughness.baseColorTexture.extensions},
      {"normalTexture", m.normalTexture.index, m.normalTexture.texCoord, &m.normalTexture.extensions},
      {"emissiveTexture", m.emissiveTexture.index, m.emissiveTexture.texCoord, &m.emissiveTexture.extensions},
  };
  for (const Candidate& c : candidates) {
    if (c.index < 0 || c.tex_coord != uv_set) continue;
    slot.name = c.name;
    const auto ext = c.extensions->find(kTransform);
    if (ext != c.extensions->end() && ext->second.IsObject()) {
      slot.has_transform = true;
      slot.transform = ext->second;
      slot.matrix = transform_matrix(ext->second);
      if (ext->second.Has("texCoord") && ext->second.Get("texCoord").IsNumber()) {
        slot.set = ext->second.Get("texCoord").GetNumberAsInt();
      }
    }
    break;
  }
  return slot;
}

UvFigures measure_uvs(std::span<const glm::dvec2> corner_uv, std::span<const glm::vec3> corner_world, int resolution) {
  UvFigures f;
  const std::size_t triangles = corner_uv.size() / 3;
  f.lo = glm::dvec2(std::numeric_limits<double>::infinity());
  f.hi = -f.lo;
  double no_area = 0.0;
  std::size_t outside = 0;
  for (std::size_t t = 0; t < triangles; ++t) {
    const glm::dvec2 a = corner_uv[3 * t], b = corner_uv[3 * t + 1], c = corner_uv[3 * t + 2];
    const glm::dvec3 p(corner_world[3 * t]), q(corner_world[3 * t + 1]), r(corner_world[3 * t + 2]);
    const double world = 0.5 * glm::length(glm::cross(q - p, r - p));
    const double uv = 0.5 * std::abs((b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y));
    f.world_area += world;
    f.uv_area += uv;
    if (!(uv > kNoUvArea)) no_area += world;
    for (const glm::dvec2& x : {a, b, c}) {
      f.lo = glm::min(f.lo, x);
      f.hi = glm::max(f.hi, x);
      if (!(x.x >= -kUvSlack && x.y >= -kUvSlack && x.x <= 1.0 + kUvSlack && x.y <= 1.0 + kUvSlack)) ++outside;
    }
  }
  if (triangles == 0) return f;
  f.no_area_share = f.world_area > 0.0 ? no_area / f.world_area : 1.0;
  f.outside_share = static_cast<double>(outside) / static_cast<double>(3 * triangles);

  // Overlap: sample points strictly inside each triangle, against how many distinct points that is.
  const auto n = static_cast<std::size_t>(resolution);
  std::vector<std::uint8_t> count(n * n, 0);
  std::size_t per_triangle = 0, distinct = 0;
  const double res = resolution;
  for (std::size_t t = 0; t < triangles; ++t) {
    glm::dvec2 v[3];
    for (std::size_t k = 0; k < 3; ++k) v[k] = glm::clamp(corner_uv[3 * t + k], glm::dvec2(0.0), glm::dvec2(1.0)) * res;
    const double area2 = (v[1].x - v[0].x) * (v[2].y - v[0].y) - (v[2].x - v[0].x) * (v[1].y - v[0].y);
    if (area2 == 0.0) continue;
    const double sign = area2 > 0.0 ? 1.0 : -1.0;
    const glm::dvec2 lo = glm::min(glm::min(v[0], v[1]), v[2]), hi = glm::max(glm::max(v[0], v[1]), v[2]);
    const int x0 = std::max(0, static_cast<int>(std::floor(lo.x - 0.5))), x1 = std::min(resolution - 1, static_cast<int>(std::ceil(hi.x - 0.5)));
    const int y0 = std::max(0, static_cast<int>(std::floor(lo.y - 0.5))), y1 = std::min(resolution - 1, static_cast<int>(std::ceil(hi.y - 0.5)));
    for (int y = y0; y <= y1; ++y) {
      for (int x = x0; x <= x1; ++x) {
        const glm::dvec2 s(x + 0.5, y + 0.5);
        bool inside = true;
        for (std::size_t e = 0; e < 3 && inside; ++e) {
          const glm::dvec2 a = v[e], b = v[(e + 1) % 3];
          inside = sign * ((b.x - a.x) * (s.y - a.y) - (s.x - a.x) * (b.y - a.y)) > 0.0;
        }
        if (!inside) continue;
        std::uint8_t& c = count[static_cast<std::size_t>(y) * n + static_cast<std::size_t>(x)];
        if (c == 0) ++distinct;
        c = static_cast<std::uint8_t>(std::min(255, c + 1));
        ++per_triangle;
      }
    }
  }
  f.overlap_share = per_triangle > 0 ? static_cast<double>(per_triangle - distinct) / static_cast<double>(per_triangle) : 0.0;
  return f;
}

std::string unusable_reason(const UvFigures& f) {
  char text[256];
  if (f.no_area_share > kMaxNoAreaShare) {
    std::snprintf(text, sizeof text, "covers no area (%.0f%% of the surface maps to zero UV area; UV area %.3g of the texture)",
                  100.0 * f.no_area_share, f.uv_area);
    return text;
  }
  if (f.outside_share > 0.0) {
    std::snprintf(text, sizeof text, "leaves [0, 1] (runs from (%.3g, %.3g) to (%.3g, %.3g); %.1f%% of corners outside)", f.lo.x,
                  f.lo.y, f.hi.x, f.hi.y, 100.0 * f.outside_share);
    return text;
  }
  if (f.overlap_share > kMaxOverlapShare) {
    std::snprintf(text, sizeof text, "overlaps itself (%.1f%% of the mapped area is shared by several triangles, more than %.0f%%)",
                  100.0 * f.overlap_share, 100.0 * kMaxOverlapShare);
    return text;
  }
  return "";
}

}  // namespace exao::bake
