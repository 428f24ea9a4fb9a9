// Vertex bakes: the analytic answer of plane-pair, what lands in COLOR_0 and
// _AO, an existing COLOR_0 multiplied, meshes split per node where their AO differs.

#include <gtest/gtest.h>

#include <tiny_gltf.h>

#include <cmath>
#include <cstring>

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

tinygltf::Model load(const std::filesystem::path& path) {
  tinygltf::TinyGLTF context;
  context.SetImageLoader([](tinygltf::Image*, const int, std::string*, std::string*, int, int, const unsigned char*, int,
                            void*) { return true; },
                         nullptr);
  tinygltf::Model model;
  std::string err, warn;
  const bool ok = path.extension() == ".glb" ? context.LoadBinaryFromFile(&model, &err, &warn, path.string())
                                             : context.LoadASCIIFromFile(&model, &err, &warn, path.string());
  EXPECT_TRUE(ok) << err;
  return model;
}

// A float accessor's values (tightly packed, as exao writes them).
std::vector<float> floats(const tinygltf::Model& model, int accessor) {
  const tinygltf::Accessor& acc = model.accessors[static_cast<std::size_t>(accessor)];
  EXPECT_EQ(acc.componentType, TINYGLTF_COMPONENT_TYPE_FLOAT);
  const tinygltf::BufferView& view = model.bufferViews[static_cast<std::size_t>(acc.bufferView)];
  const std::size_t n = acc.count * static_cast<std::size_t>(tinygltf::GetNumComponentsInType(static_cast<std::uint32_t>(acc.type)));
  std::vector<float> out(n);
  std::memcpy(out.data(), model.buffers[static_cast<std::size_t>(view.buffer)].data.data() + view.byteOffset + acc.byteOffset,
              n * sizeof(float));
  return out;
}

TEST(BakeVertex, PlanePairMatchesTheAnalyticAnswer) {
  Result<bake::Document> document = bake::Document::open("plane-pair");
  ASSERT_TRUE(document) << document.error().message;
  const BvhAo ao(document->scene(), 1.0f, 128);
  Result<bake::BakeResult> result = bake::bake(*document, {}, ao.function());
  ASSERT_TRUE(result) << result.error().message;

  // A floor point under the ceiling at h = 0.5, r = 1, constant falloff: AO = (h'/r)^2 with h'
  // the height above the ray origin p + eps n (DESIGN.md section 6). The sampling error is the
  // one tests/embree_reference_test.cpp derives for a stratified pattern: a few of the ~sqrt(N)
  // points along the boundary circle fall either way, 1.5 / sqrt(N) per receiver; the jittered
  // frames average it away, so the mean is four times tighter.
  const double h = 0.5 - static_cast<double>(ao.engine.rays().origin_offset);
  const double expected = h * h;
  const double sampling_error = 1.5 / std::sqrt(128.0);
  std::size_t checked = 0;
  double worst = 0.0, mean = 0.0;
  for (std::size_t i = 0; i < result->receivers.size(); ++i) {
    const Receiver& r = result->receivers[i];
    const bool floor_centre = r.position.y == 0.0f && std::abs(r.position.x) <= 2.5f && std::abs(r.position.z) <= 2.5f;
    if (!floor_centre) continue;
    EXPECT_EQ(r.normal, glm::vec3(0.0f, 1.0f, 0.0f));
    EXPECT_NEAR(result->ao[i], expected, sampling_error) << "at " << r.position.x << ", " << r.position.z;
    worst = std::max(worst, std::abs(static_cast<double>(result->ao[i]) - expected));
    mean += result->ao[i];
    ++checked;
  }
  ASSERT_GT(checked, 400u);
  mean /= static_cast<double>(checked);
  EXPECT_NEAR(mean, expected, 0.25 * sampling_error);
  std::printf("plane-pair: %zu floor vertices, (h/r)^2 = %.4f, mean AO %.4f, worst vertex off by %.4f (%.1f rays of 128)\n",
              checked, expected, mean, worst, worst * 128.0);

  // Keys are distinct: each vertex has its own rays.
  std::vector<std::uint64_t> keys;
  for (const Receiver& r : result->receivers) keys.push_back(r.key);
  std::sort(keys.begin(), keys.end());
  EXPECT_EQ(std::adjacent_find(keys.begin(), keys.end()), keys.end());

  // And the file holds those values in COLOR_0, grey.
  test::TempDir dir;
  std::vector<std::string> notes;
  ASSERT_TRUE(bake::save(*document, *result, {(dir / "pp.glb").string()}, notes));
  const tinygltf::Model model = load(dir / "pp.glb");
  ASSERT_EQ(model.meshes.size(), 1u);
  const tinygltf::Primitive& prim = model.meshes[0].primitives[0];
  const std::vector<float> color = floats(model, prim.attributes.at("COLOR_0"));
  const std::vector<float> position = floats(model, prim.attributes.at("POSITION"));
  ASSERT_EQ(color.size(), position.size());
  std::size_t matched = 0;
  for (std::size_t i = 0; i < result->receivers.size(); ++i) {
    for (std::size_t v = 0; v < position.size() / 3; ++v) {
      if (glm::vec3(position[3 * v], position[3 * v + 1], position[3 * v + 2]) == result->receivers[i].position) {
        EXPECT_EQ(color[3 * v], result->ao[i]);
        EXPECT_EQ(color[3 * v + 1], result->ao[i]);
        EXPECT_EQ(color[3 * v + 2], result->ao[i]);
        ++matched;
        break;
      }
    }
    if (matched >= 50) break;
  }
  EXPECT_EQ(matched, 50u);
}

TEST(BakeVertex, AttributeModeWritesAScalarAo) {
  Result<bake::Document> document = bake::Document::open("plane-pair");
  ASSERT_TRUE(document);
  const BvhAo ao(document->scene(), 1.0f, 64);
  bake::BakeOptions options;
  options.channel = bake::VertexChannel::Attribute;
  Result<bake::BakeResult> result = bake::bake(*document, options, ao.function());
  ASSERT_TRUE(result) << result.error().message;
  test::TempDir dir;
  std::vector<std::string> notes;
  ASSERT_TRUE(bake::save(*document, *result, {(dir / "pp.gltf").string()}, notes));
  EXPECT_TRUE(std::filesystem::exists(dir / "pp.bin"));
  const tinygltf::Model model = load(dir / "pp.gltf");
  const tinygltf::Primitive& prim = model.meshes[0].primitives[0];
  EXPECT_EQ(prim.attributes.count("COLOR_0"), 0u);
  const tinygltf::Accessor& acc = model.accessors[static_cast<std::size_t>(prim.attributes.at("_AO"))];
  EXPECT_EQ(acc.type, TINYGLTF_TYPE_SCALAR);
  const std::vector<float> values = floats(model, prim.attributes.at("_AO"));
  EXPECT_EQ(*std::min_element(values.begin(), values.end()), *std::min_element(result->ao.begin(), result->ao.end()));
}

// A floor and a ceiling quad with COLOR_0 = (0.5, 1, 1, 0.25): after the bake, RGB is darkened
// by the AO and alpha is kept.
TEST(BakeVertex, AnExistingColorIsMultiplied) {
  test::TempDir dir;
  const float data[] = {
      -2, 0, 2,  2, 0, 2,  2, 0, -2,  -2, 0, -2,        // floor, facing +Y
      -2, 1, -2, 2, 1, -2, 2, 1, 2,   -2, 1, 2,         // ceiling, facing -Y
  };
  std::vector<float> colors;
  for (int i = 0; i < 8; ++i) colors.insert(colors.end(), {0.5f, 1.0f, 1.0f, 0.25f});
  const std::uint16_t indices[] = {0, 1, 2, 0, 2, 3, 4, 5, 6, 4, 6, 7};
  std::string bin(reinterpret_cast<const char*>(data), sizeof data);
  bin.append(reinterpret_cast<const char*>(colors.data()), colors.size() * sizeof(float));
  bin.append(reinterpret_cast<const char*>(indices), sizeof indices);
  test::write_file(dir / "quads.bin", bin);
  test::write_file(dir / "quads.gltf", R"({
    "asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0, "name": "quads"}],
    "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "COLOR_0": 1}, "indices": 2}]}],
    "buffers": [{"uri": "quads.bin", "byteLength": 248}],
    "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 96}, {"buffer": 0, "byteOffset": 96, "byteLength": 128},
                    {"buffer": 0, "byteOffset": 224, "byteLength": 24}],
    "accessors": [{"bufferView": 0, "componentType": 5126, "count": 8, "type": "VEC3", "min": [-2, 0, -2], "max": [2, 1, 2]},
                  {"bufferView": 1, "componentType": 5126, "count": 8, "type": "VEC4"},
                  {"bufferView": 2, "componentType": 5123, "count": 12, "type": "SCALAR"}]})");
  Result<bake::Document> document = bake::Document::open((dir / "quads.gltf").string());
  ASSERT_TRUE(document) << document.error().message;
  const BvhAo ao(document->scene(), 2.0f, 64);
  Result<bake::BakeResult> result = bake::bake(*document, {}, ao.function());
  ASSERT_TRUE(result) << result.error().message;
  ASSERT_EQ(result->notes.size(), 1u);
  EXPECT_NE(result->notes[0].find("COLOR_0"), std::string::npos) << result->notes[0];
  std::vector<std::string> notes;
  ASSERT_TRUE(bake::save(*document, *result, {(dir / "out.glb").string()}, notes));
  const tinygltf::Model model = load(dir / "out.glb");
  const std::vector<float> color = floats(model, model.meshes[0].primitives[0].attributes.at("COLOR_0"));
  ASSERT_EQ(color.size(), 32u);
  const std::vector<float>& vertex_ao = result->part_vertex_ao[0];
  for (std::size_t v = 0; v < 8; ++v) {
    EXPECT_LT(vertex_ao[v], 1.0f);  // a 1 x 4 x 4 box open on its sides: every corner is partly occluded
    EXPECT_FLOAT_EQ(color[4 * v], 0.5f * vertex_ao[v]);
    EXPECT_FLOAT_EQ(color[4 * v + 1], vertex_ao[v]);
    EXPECT_FLOAT_EQ(color[4 * v + 3], 0.25f);
  }
}

// CesiumMilkTruck draws mesh 'Wheels' from two nodes, front and back: their AO differs, so the
// second node gets a mesh of its own; everything else in the file is still there.
TEST(BakeVertex, AMeshDrawnByTwoNodesIsSplit) {
  const auto path = test::real_scene("CesiumMilkTruck/glTF/CesiumMilkTruck.gltf");
  EXAO_REQUIRE_SCENE(path);
  Result<bake::Document> document = bake::Document::open(path.string());
  ASSERT_TRUE(document) << document.error().message;
  const BvhAo ao(document->scene(), 0.3f, 64);
  Result<bake::BakeResult> result = bake::bake(*document, {}, ao.function());
  ASSERT_TRUE(result) << result.error().message;
  EXPECT_EQ(result->meshes_split, 1u);
  bool said = false;
  for (const std::string& note : result->notes) said |= note.find("'Wheels' is drawn by 2 nodes") != std::string::npos;
  EXPECT_TRUE(said);
  test::TempDir dir;
  std::vector<std::string> notes;
  ASSERT_TRUE(bake::save(*document, *result, {(dir / "truck.gltf").string()}, notes));
  const tinygltf::Model before = load(path);
  const tinygltf::Model after = load(dir / "truck.gltf");
  EXPECT_EQ(after.nodes.size(), before.nodes.size());
  EXPECT_EQ(after.materials.size(), before.materials.size());
  EXPECT_EQ(after.textures.size(), before.textures.size());
  EXPECT_EQ(after.images.size(), before.images.size());
  EXPECT_EQ(after.images[0].uri, before.images[0].uri);
  EXPECT_EQ(after.meshes.size(), before.meshes.size() + 1);
  EXPECT_EQ(after.animations.size(), before.animations.size());
  int wheels = 0;
  for (const tinygltf::Node& node : after.nodes) {
    if (node.name.rfind("Wheels", 0) == 0) {
      ++wheels;
      EXPECT_EQ(after.meshes[static_cast<std::size_t>(node.mesh)].primitives[0].attributes.count("COLOR_0"), 1u);
      EXPECT_EQ(after.meshes[static_cast<std::size_t>(node.mesh)].primitives[0].attributes.count("NORMAL"), 1u);
    }
  }
  EXPECT_EQ(wheels, 2);
  EXPECT_NE(after.nodes[0].mesh, after.nodes[2].mesh);
}

// --normals file takes the NORMAL attribute (rotated into world space with the node).
TEST(BakeVertex, FileNormalsAreUsedWhenAsked) {
  const auto path = test::real_scene("Duck/glTF-Binary/Duck.glb");
  EXAO_REQUIRE_SCENE(path);
  Result<bake::Document> document = bake::Document::open(path.string());
  ASSERT_TRUE(document);
  const BvhAo ao(document->scene(), 20.0f, 32);
  bake::BakeOptions options;
  options.normals = bake::NormalSource::File;
  Result<bake::BakeResult> file = bake::bake(*document, options, ao.function());
  ASSERT_TRUE(file) << file.error().message;
  Result<bake::Document> again = bake::Document::open(path.string());
  Result<bake::BakeResult> geometric = bake::bake(*again, {}, ao.function());
  ASSERT_TRUE(geometric);
  ASSERT_EQ(file->receivers.size(), geometric->receivers.size());
  std::size_t differ = 0;
  double mean_dot = 0.0;
  for (std::size_t i = 0; i < file->receivers.size(); ++i) {
    EXPECT_EQ(file->receivers[i].position, geometric->receivers[i].position);
    differ += file->receivers[i].normal != geometric->receivers[i].normal ? 1 : 0;
    mean_dot += glm::dot(file->receivers[i].normal, geometric->receivers[i].normal);
  }
  EXPECT_GT(differ, file->receivers.size() / 2);
  EXPECT_GT(mean_dot / static_cast<double>(file->receivers.size()), 0.9);  // same surface, near normals
}

}  // namespace
}  // namespace exao
