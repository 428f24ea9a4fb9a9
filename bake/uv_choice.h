#pragma once
// Which UVs an AO map is laid out by (exao bake --uv auto|file|generate): the file's set, seen
// through the KHR_texture_transform of the texture slot the AO shares, and the figures that say
// whether that set can hold AO. Internal to exao_bake (it exposes tinygltf).

#include <tiny_gltf.h>

#include <span>
#include <string>

#include <glm/glm.hpp>

namespace exao::bake {

/// The texture slot whose UVs the AO map shares: the material's occlusionTexture, else its
/// metallicRoughnessTexture (ORM packing puts AO in the red channel of that image), else any
/// other texture of the material that reads the same set (a quantised set's dequantising
/// transform is on every texture that reads it, KHR_mesh_quantization section "Texture
/// coordinates"). Only a slot that reads `uv_set` counts.
struct AoSlot {
  std::string name;             // "occlusionTexture", ...; empty when no slot reads the set
  int tex_coord = 0;            // the slot's texCoord (== uv_set)
  int set = 0;                  // the set actually read: the transform's texCoord override, if any
  bool has_transform = false;
  tinygltf::Value transform;    // the slot's KHR_texture_transform object, copied onto the AO map
  glm::dmat3 matrix{1.0};       // uv' = matrix * (u, v, 1), KHR_texture_transform's T * R * S
};

[[nodiscard]] AoSlot ao_slot(const tinygltf::Model& model, int material, int uv_set);

/// What a set of UV triangles covers (corner UVs in texture space, three per triangle, with the
/// triangles' world-space corners beside them).
struct UvFigures {
  double world_area = 0.0;       // sum of the triangles' 3D areas
  double uv_area = 0.0;          // sum of their UV areas, in units of the whole texture
  double no_area_share = 0.0;    // share of the 3D area on triangles whose UV area is (close to) zero
  double outside_share = 0.0;    // share of corners outside [0, 1] (beyond rounding)
  glm::dvec2 lo{0.0}, hi{0.0};   // UV bounds
  double overlap_share = 0.0;    // share of the mapped area that more than one triangle maps to
};

/// Measures the figures; overlap is counted at `resolution`^2 sample points (texel centres):
/// (samples inside some triangle, counted per triangle, minus samples inside any) / the former.
[[nodiscard]] UvFigures measure_uvs(std::span<const glm::dvec2> corner_uv, std::span<const glm::vec3> corner_world,
                                    int resolution);

/// The thresholds of --uv auto: a set is replaced when more than half of the surface has no UV
/// area, any corner leaves [0, 1], or more than kMaxOverlapShare of the mapped area is shared.
inline constexpr double kMaxNoAreaShare = 0.5;
inline constexpr double kMaxOverlapShare = 0.01;
/// UV triangles smaller than this share of the texture (1e-4 of a texel of a 1024^2 map) count
/// as having no area; corners this far outside [0, 1] are rounding of an edge on the border.
inline constexpr double kNoUvArea = 1e-10;
inline constexpr double kUvSlack = 1e-3;

/// Why the figures make `auto` replace the set, or "" when they do not.
[[nodiscard]] std::string unusable_reason(const UvFigures& figures);

}  // namespace exao::bake
