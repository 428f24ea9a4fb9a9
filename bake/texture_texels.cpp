// Texture bake step 6 (bake/texture_steps.h): receiver normals per triangle corner, and each
// map's texel receivers (bake/texel_receivers.h).

#include <cmath>
#include <map>

#include "bake/corner_normals.h"
#include "bake/part_geometry.h"
#include "bake/texture_steps.h"

namespace exao::bake {

Result<void> texel_receivers_of(const tinygltf::Model& model, const ModelWalk& walk, const BakeOptions& options,
                                TexturePlan& plan, BakeResult& result) {
  // Receiver normals per triangle corner: crease-aware geometric ones, or the file's.
  std::vector<glm::vec3> corner_positions;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> corner_source;  // part, vertex
  for (std::size_t p = 0; p < walk.parts.size(); ++p) {
    for (const std::uint32_t v : part_corners(walk, p)) {
      corner_positions.push_back(walk.parts[p].world[v]);
      corner_source.emplace_back(static_cast<std::uint32_t>(p), v);
    }
  }
  std::vector<glm::vec3> normals = corner_normals(corner_positions, kCreaseDegrees);
  if (options.normals == NormalSource::File) {
    std::size_t without = 0;
    std::map<std::uint32_t, std::vector<glm::vec3>> per_part;
    for (std::size_t p = 0; p < walk.parts.size(); ++p) {
      auto from_file = file_normals(model, walk, p);
      if (!from_file) return std::unexpected(from_file.error());
      if (from_file->empty()) ++without;
      per_part[static_cast<std::uint32_t>(p)] = std::move(*from_file);
    }
    for (std::size_t c = 0; c < normals.size(); ++c) {
      const std::vector<glm::vec3>& n = per_part[corner_source[c].first];
      if (!n.empty() && n[corner_source[c].second] != glm::vec3(0.0f)) normals[c] = n[corner_source[c].second];
    }
    if (without > 0) {
      result.notes.push_back(std::to_string(without) + " primitive(s) have no NORMAL: their texels use geometric normals");
    }
  }

  // Texel receivers, map by map.
  const int k = static_cast<int>(std::lround(std::sqrt(static_cast<double>(options.texel_samples))));
  const int size = options.texture_size;
  std::vector<TexelReceivers>& texels = plan.texels;
  texels.assign(result.maps.size(), {});
  for (std::size_t m = 0; m < result.maps.size(); ++m) {
    std::vector<UvTriangle> triangles;
    std::size_t corner = 0;
    for (std::size_t p = 0; p < walk.parts.size(); ++p) {
      const std::vector<std::uint32_t> corners = part_corners(walk, p);
      if (result.part_map[p] != static_cast<int>(m)) {
        corner += corners.size();
        continue;
      }
      for (std::size_t t = 0; t + 2 < corners.size(); t += 3, corner += 3) {
        UvTriangle tri;
        for (std::size_t j = 0; j < 3; ++j) {
          tri.uv[j] = glm::dvec2(result.part_corner_uv[p][t + j]) * static_cast<double>(size);
          tri.position[j] = walk.parts[p].world[corners[t + j]];
          tri.normal[j] = normals[corner + j];
        }
        tri.source = static_cast<std::uint32_t>(p);
        triangles.push_back(tri);
      }
    }
    texels[m] = texel_receivers(triangles, size, size, k, result.receivers.size());
    AoMap& map = result.maps[m];
    map.covered_texels = texels[m].covered_texels;
    map.overlap_texels = texels[m].overlap_texels;
    result.receivers.insert(result.receivers.end(), texels[m].receivers.begin(), texels[m].receivers.end());
    result.receiver_texel.insert(result.receiver_texel.end(), texels[m].texel.begin(), texels[m].texel.end());
    result.receiver_map.insert(result.receiver_map.end(), texels[m].receivers.size(), static_cast<std::uint32_t>(m));
    texels[m].receivers = {};
  }
  return {};
}

}  // namespace exao::bake
