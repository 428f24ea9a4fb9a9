// Texture bakes: texels hold the AO of receivers at their centres, partly
// covered texels count, the margin fills around charts, both sides of a UV seam agree, and
// overlapping UVs and missing or tiling UVs are reported.

#include <gtest/gtest.h>

#include <tiny_gltf.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <map>

#include "bake/bake.h"
#include "bake/document.h"
#include "bake/save.h"
#include "core/shadow_rays.h"
#include "lut/mask_engine.h"
#include "lut/triangle_set.h"
#include "tests/engine_ao.h"
#include "tests/test_support.h"

namespace exao {
namespace {

using test::BvhAo;

// A 4 x 4 floor at y = 0 (facing up) under a ceiling at y = 1 (facing down), one primitive each.
// The floor's UVs map x, z in [-2, 2] to [0.1, 0.9], so chart borders can cut texels in part;
// the ceiling's are `ceiling_uv` times the same (1: the same texels; 2: partly outside [0, 1]).
void write_quads(const std::filesystem::path& folder, bool with_uv, bool shared_material, float ceiling_uv = 1.0f) {
  const float positions[] = {-2, 0, 2, 2, 0, 2, 2, 0, -2, -2, 0, -2, -2, 1, -2, 2, 1, -2, 2, 1, 2, -2, 1, 2};
  std::vector<float> uv;
  for (int v = 0; v < 8; ++v) {
    const float x = positions[3 * v], z = positions[3 * v + 2];
    const float s = v < 4 ? 1.0f : ceiling_uv;
    uv.insert(uv.end(), {s * (0.1f + 0.8f * (x + 2.0f) / 4.0f), s * (0.1f + 0.8f * (z + 2.0f) / 4.0f)});
  }
  const std::uint16_t indices[] = {0, 1, 2, 0, 2, 3, 0, 1, 2, 0, 2, 3};
  std::string bin(reinterpret_cast<const char*>(positions), sizeof positions);
  bin.append(reinterpret_cast<const char*>(indices), sizeof indices);
  bin.append(reinterpret_cast<const char*>(uv.data()), uv.size() * sizeof(float));
  test::write_file(folder / "quads.bin", bin);
  const auto attributes = [&](int position, int texcoord) {
    return "{\"POSITION\": " + std::to_string(position) +
           (with_uv ? ", \"TEXCOORD_0\": " + std::to_string(texcoord) : std::string()) + "}";
  };
  test::write_file(folder / "quads.gltf", R"({
    "asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
    "materials": [{"name": "floor"}, {"name": "ceiling"}],
    "meshes": [{"primitives": [{"attributes": )" + attributes(0, 4) + R"(, "indices": 2, "material": 0},
                               {"attributes": )" + attributes(1, 5) + R"(, "indices": 3, "material": )" +
                                   (shared_material ? "0" : "1") + R"(}]}],
    "buffers": [{"uri": "quads.bin", "byteLength": 184}],
    "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 96}, {"buffer": 0, "byteOffset": 96, "byteLength": 24},
                    {"buffer": 0, "byteOffset": 120, "byteLength": 64}],
    "accessors": [{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [-2, 0, -2], "max": [2, 0, 2]},
                  {"bufferView": 0, "byteOffset": 48, "componentType": 5126, "count": 4, "type": "VEC3", "min": [-2, 1, -2], "max": [2, 1, 2]},
                  {"bufferView": 1, "componentType": 5123, "count": 6, "type": "SCALAR"},
                  {"bufferView": 1, "byteOffset": 12, "componentType": 5123, "count": 6, "type": "SCALAR"},
                  {"bufferView": 2, "componentType": 5126, "count": 4, "type": "VEC2"},
                  {"bufferView": 2, "byteOffset": 32, "componentType": 5126, "count": 4, "type": "VEC2"}]})");
}

TEST(BakeTexture, TexelsHoldTheAoOfTheirCentres) {
  test::TempDir dir;
  write_quads(dir.path(), true, false);
  Result<bake::Document> document = bake::Document::open((dir / "quads.gltf").string());
  ASSERT_TRUE(document) << document.error().message;
  ASSERT_EQ(document->scene().triangle_count(), 4u);
  const BvhAo ao(document->scene(), 1.5f, 128, lut::MaskMode::Exact);
  bake::BakeOptions options;
  options.target = bake::Target::Texture;
  options.texture_size = 45;  // uv 0.1..0.9 is texel 4.5..40.5: texels 4 and 40 are half covered
  options.texel_samples = 1;
  options.margin = 2;
  Result<bake::BakeResult> result = bake::bake(*document, options, ao.function());
  ASSERT_TRUE(result) << result.error().message;
  ASSERT_EQ(result->maps.size(), 2u);
  const bake::AoMap& floor = result->maps[0].material == 0 ? result->maps[0] : result->maps[1];
  const std::uint32_t floor_index = result->maps[0].material == 0 ? 0u : 1u;
  const int size = floor.size;

  const int first = 4, last = 40, side = last - first + 1;
  std::size_t covered = 0;
  for (const std::uint8_t f : floor.filled) covered += f == 1 ? 1 : 0;
  EXPECT_EQ(covered, static_cast<std::size_t>(side * side));

  // Each texel's receiver sits where the texel centre maps to on the floor (the nearest point of
  // the floor for a border texel whose centre falls just outside), facing up; its AO, computed
  // again from that analytic point with the same key, is the texel's value.
  std::vector<Receiver> analytic;
  std::vector<std::size_t> texel_of;
  for (std::size_t r = 0; r < result->receivers.size(); ++r) {
    if (result->receiver_map[r] != floor_index) continue;
    const std::uint32_t t = result->receiver_texel[r];
    const double u = (t % static_cast<std::uint32_t>(size) + 0.5) / size, v = (t / static_cast<std::uint32_t>(size) + 0.5) / size;
    const glm::vec3 expected(static_cast<float>(std::clamp((u - 0.1) / 0.8 * 4.0 - 2.0, -2.0, 2.0)), 0.0f,
                             static_cast<float>(std::clamp((v - 0.1) / 0.8 * 4.0 - 2.0, -2.0, 2.0)));
    const Receiver& got = result->receivers[r];
    EXPECT_NEAR(got.position.x, expected.x, 1e-5f);
    EXPECT_EQ(got.position.y, 0.0f);
    EXPECT_NEAR(got.position.z, expected.z, 1e-5f);
    EXPECT_NEAR(got.normal.y, 1.0f, 1e-6f);
    analytic.push_back({expected, {0.0f, 1.0f, 0.0f}, got.key});
    texel_of.push_back(t);
  }
  ASSERT_EQ(analytic.size(), static_cast<std::size_t>(side * side));
  const std::vector<float> again = ao(analytic);
  std::size_t identical = 0;
  for (std::size_t i = 0; i < analytic.size(); ++i) {
    // A position a few ulps away may flip a ray that grazes a triangle edge, no more.
    EXPECT_NEAR(floor.ao[texel_of[i]], again[i], 2.0f / 128.0f);
    identical += floor.ao[texel_of[i]] == again[i] ? 1 : 0;
  }
  EXPECT_GE(identical, analytic.size() * 99 / 100);

  // The margin: two rings of texels around the chart take its border's values, the rest is open.
  std::size_t margin = 0, background = 0;
  for (int y = 0; y < size; ++y) {
    for (int x = 0; x < size; ++x) {
      const std::size_t i = static_cast<std::size_t>(y * size + x);
      const int outside = std::max({first - x, x - last, first - y, y - last, 0});
      if (outside >= 1 && outside <= 2) {
        EXPECT_EQ(floor.filled[i], 2) << x << ", " << y;
        EXPECT_LT(floor.ao[i], 1.0f);
        ++margin;
      } else if (outside > 2) {
        EXPECT_EQ(floor.filled[i], 0);
        EXPECT_EQ(floor.ao[i], 1.0f);
        ++background;
      }
    }
  }
  EXPECT_EQ(margin, static_cast<std::size_t>((side + 4) * (side + 4) - side * side));
  EXPECT_GT(background, 0u);
}

TEST(BakeTexture, PartlyCoveredTexelsCount) {
  test::TempDir dir;
  write_quads(dir.path(), true, false);
  Result<bake::Document> document = bake::Document::open((dir / "quads.gltf").string());
  ASSERT_TRUE(document);
  const BvhAo ao(document->scene(), 1.5f, 32);
  bake::BakeOptions options;
  options.target = bake::Target::Texture;
  options.texture_size = 37;  // 0.1 * 37 = 3.7: the border texels are cut in part
  options.texel_samples = 4;
  Result<bake::BakeResult> result = bake::bake(*document, options, ao.function());
  ASSERT_TRUE(result) << result.error().message;
  const bake::AoMap& floor = result->maps[0].material == 0 ? result->maps[0] : result->maps[1];
  // uv 0.1..0.9 is texel 3.7..33.3: texels 3..33 are touched, 31 per side.
  std::size_t covered = 0;
  for (int y = 0; y < 37; ++y) {
    for (int x = 0; x < 37; ++x) {
      const bool inside = x >= 3 && x <= 33 && y >= 3 && y <= 33;
      EXPECT_EQ(floor.filled[static_cast<std::size_t>(y * 37 + x)] == 1, inside) << x << ", " << y;
      covered += inside ? 1 : 0;
    }
  }
  EXPECT_EQ(floor.covered_texels, covered);
  // Every receiver lies on a quad, even those of texels whose samples mostly miss it.
  for (const Receiver& r : result->receivers) {
    EXPECT_LE(std::abs(r.position.x), 2.0f);
    EXPECT_LE(std::abs(r.position.z), 2.0f);
  }
}

// A built-in scene has no UVs: the box-projection atlas cuts the sphere of sphere-on-plane into
// charts. Where a chart border (a UV seam) crosses the smooth sphere, the map read on either side
// of the seam (bilinearly, as a viewer reads it) gives the same AO within the sampling error.
TEST(BakeTexture, BothSidesOfASeamAgree) {
  const int size = 256;
  bake::ConvertOptions convert;
  convert.atlas_size = size;
  convert.atlas_padding = 10;
  Result<bake::Document> document = bake::Document::open("sphere-on-plane", convert);
  ASSERT_TRUE(document) << document.error().message;
  const int samples = 128;
  const BvhAo ao(document->scene(), 1.0f, samples);
  bake::BakeOptions options;
  options.target = bake::Target::Texture;
  options.texture_size = size;
  options.texel_samples = 4;
  Result<bake::BakeResult> result = bake::bake(*document, options, ao.function());
  ASSERT_TRUE(result) << result.error().message;
  ASSERT_EQ(result->maps.size(), 1u);
  const bake::AoMap& map = result->maps[0];
  const auto sample = [&](glm::dvec2 uv) {
    const double x = uv.x * size - 0.5, y = uv.y * size - 0.5;
    const int x0 = static_cast<int>(std::floor(x)), y0 = static_cast<int>(std::floor(y));
    const auto at = [&](int px, int py) {
      return static_cast<double>(map.ao[static_cast<std::size_t>(std::clamp(py, 0, size - 1) * size + std::clamp(px, 0, size - 1))]);
    };
    const double tx = x - x0, ty = y - y0;
    return (1 - ty) * ((1 - tx) * at(x0, y0) + tx * at(x0 + 1, y0)) + ty * ((1 - tx) * at(x0, y0 + 1) + tx * at(x0 + 1, y0 + 1));
  };

  // Seam edges: the same two 3D points joined in two triangles with different UVs.
  struct Side {
    glm::dvec2 a, b;
  };
  std::map<std::pair<std::array<float, 3>, std::array<float, 3>>, std::vector<Side>> edges;
  const auto& parts_uv = result->part_uv;
  ASSERT_EQ(parts_uv.size(), 1u);
  test::TempDir dir;
  std::vector<std::string> notes;
  ASSERT_TRUE(bake::save(*document, *result, {(dir / "s.glb").string()}, notes));
  tinygltf::Model model;
  tinygltf::TinyGLTF context;
  context.SetImageLoader([](tinygltf::Image*, const int, std::string*, std::string*, int, int, const unsigned char*, int,
                            void*) { return true; },
                         nullptr);
  std::string err, warn;
  ASSERT_TRUE(context.LoadBinaryFromFile(&model, &err, &warn, (dir / "s.glb").string())) << err;
  const tinygltf::Primitive& prim = model.meshes[0].primitives[0];
  const auto data = [&](int accessor) {
    const tinygltf::Accessor& acc = model.accessors[static_cast<std::size_t>(accessor)];
    const tinygltf::BufferView& view = model.bufferViews[static_cast<std::size_t>(acc.bufferView)];
    return model.buffers[0].data.data() + view.byteOffset + acc.byteOffset;
  };
  const auto* pos = reinterpret_cast<const float*>(data(prim.attributes.at("POSITION")));
  const auto* idx = reinterpret_cast<const std::uint32_t*>(data(prim.indices));
  const std::size_t index_count = model.accessors[static_cast<std::size_t>(prim.indices)].count;
  const std::vector<glm::vec2>& uv = parts_uv[0];
  for (std::size_t t = 0; t < index_count; t += 3) {
    for (std::size_t k = 0; k < 3; ++k) {
      std::uint32_t i = idx[t + k], j = idx[t + (k + 1) % 3];
      std::array<float, 3> p{pos[3 * i], pos[3 * i + 1], pos[3 * i + 2]}, q{pos[3 * j], pos[3 * j + 1], pos[3 * j + 2]};
      if (q < p) {
        std::swap(p, q);
        std::swap(i, j);
      }
      edges[{p, q}].push_back({glm::dvec2(uv[i]), glm::dvec2(uv[j])});
    }
  }
  std::vector<double> differences;
  for (const auto& [key, sides] : edges) {
    // On the lower half of the sphere (centre (0, 1, 0), radius 1), where the floor darkens it and
    // AO changes fastest, short of the contact point itself.
    const auto lower = [](const std::array<float, 3>& p) { return p[1] > 0.2f && p[1] < 1.0f; };
    if (sides.size() != 2 || !lower(key.first) || !lower(key.second)) continue;
    if (glm::distance(sides[0].a, sides[1].a) < 1e-6 && glm::distance(sides[0].b, sides[1].b) < 1e-6) continue;
    for (const double f : {0.25, 0.5, 0.75}) {
      differences.push_back(std::abs(sample(glm::mix(sides[0].a, sides[0].b, f)) - sample(glm::mix(sides[1].a, sides[1].b, f))));
    }
  }
  ASSERT_GT(differences.size(), 50u) << "the atlas should cut the sphere";
  double mean = 0.0, largest = 0.0, darkest = 1.0;
  for (const auto& [key, sides] : edges) darkest = std::min(darkest, sample(sides[0].a));
  EXPECT_LT(darkest, 0.8) << "the seams run through occluded parts";
  for (const double d : differences) {
    mean += d / static_cast<double>(differences.size());
    largest = std::max(largest, d);
  }
  // A texel averages 4 receivers of N rays: its sampling error is about 1.5 / sqrt(4 N)
  // (tests/embree_reference_test.cpp). Read at the seam, each side's value comes from about half
  // a texel inside its own chart, so the two also differ by the AO gradient across one texel:
  // the mean difference halves when the texels do (0.022 at 256, 0.010 at 512, measured), which
  // a seam error would not. Every point is within the sampling error; the mean within half.
  const double sampling_error = 1.5 / std::sqrt(4.0 * samples);
  std::printf("seams: %zu points on %zu seam edges, mean |difference| %.4f, max %.4f (sampling error %.4f)\n",
              differences.size(), differences.size() / 3, mean, largest, sampling_error);
  EXPECT_LT(mean, 0.5 * sampling_error);
  EXPECT_LT(largest, sampling_error);
}

TEST(BakeTexture, OverlappingUvsAreReported) {
  test::TempDir dir;
  write_quads(dir.path(), true, true);  // floor and ceiling: one material, the same UVs
  Result<bake::Document> document = bake::Document::open((dir / "quads.gltf").string());
  ASSERT_TRUE(document);
  const BvhAo ao(document->scene(), 1.5f, 32);
  bake::BakeOptions options;
  options.target = bake::Target::Texture;
  options.texture_size = 32;
  Result<bake::BakeResult> result = bake::bake(*document, options, ao.function());
  ASSERT_TRUE(result) << result.error().message;
  ASSERT_EQ(result->maps.size(), 1u);
  EXPECT_GT(result->maps[0].overlap_texels, 24u * 24u);
  bool said = false;
  for (const std::string& note : result->notes) said |= note.find("overlapping UVs") != std::string::npos;
  EXPECT_TRUE(said);
}

TEST(BakeTexture, MissingOrTilingUvsAreClearErrors) {
  test::TempDir dir;
  bake::BakeOptions options;
  options.target = bake::Target::Texture;
  options.uv = bake::UvMode::File;  // uv auto (the default) would generate a set instead
  // No AO is computed for bad input: the engine's progress never moves.
  const ProgressCallback never = [](std::size_t, std::size_t) { ADD_FAILURE() << "no AO is computed for bad input"; };
  write_quads(dir.path(), false, false);
  Result<bake::Document> no_uv = bake::Document::open((dir / "quads.gltf").string());
  ASSERT_TRUE(no_uv);
  Result<bake::BakeResult> result = bake::bake(*no_uv, options, BvhAo(no_uv->scene(), 1.0f, 32).function(), never);
  ASSERT_FALSE(result);
  EXPECT_NE(result.error().message.find("quads.gltf"), std::string::npos) << result.error().message;
  EXPECT_NE(result.error().message.find("no TEXCOORD_0"), std::string::npos) << result.error().message;
  EXPECT_NE(result.error().message.find("bake per vertex"), std::string::npos) << result.error().message;

  write_quads(dir.path(), true, false, 2.0f);  // the ceiling's UVs reach 1.8
  Result<bake::Document> tiling = bake::Document::open((dir / "quads.gltf").string());
  ASSERT_TRUE(tiling);
  result = bake::bake(*tiling, options, BvhAo(tiling->scene(), 1.0f, 32).function(), never);
  ASSERT_FALSE(result);
  EXPECT_NE(result.error().message.find("outside [0, 1]"), std::string::npos) << result.error().message;
  EXPECT_NE(result.error().message.find("bake per vertex"), std::string::npos) << result.error().message;

  options.texel_samples = 3;
  write_quads(dir.path(), true, false);
  Result<bake::Document> fine = bake::Document::open((dir / "quads.gltf").string());
  result = bake::bake(*fine, options, BvhAo(fine->scene(), 1.0f, 32).function(), never);
  ASSERT_FALSE(result);
  // A library error names the option, never a flag (the exao program maps it to --texel-samples).
  EXPECT_EQ(result.error().message.rfind("texel_samples: ", 0), 0u) << result.error().message;
}

}  // namespace
}  // namespace exao
