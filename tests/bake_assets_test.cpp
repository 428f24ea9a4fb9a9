// Bakes of real-world assets (issue 15): UV sets that cannot hold AO get a generated one under
// --uv auto, quantised and transformed UVs, Draco and meshopt compressed files (made here with
// Debian's draco_transcoder and gltfpack), and the ground plane.

#include <gtest/gtest.h>

#include <tiny_gltf.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <unordered_map>

#include "bake/bake.h"
#include "bake/document.h"
#include "bake/document_impl.h"
#include "bake/save.h"
#include "bvh/occlusion.h"
#include "io/load_scene.h"
#include "core/shadow_rays.h"
#include "lut/mask_engine.h"
#include "lut/triangle_set.h"
#include "tests/engine_ao.h"
#include "tests/test_support.h"

namespace exao {
namespace {

namespace fs = std::filesystem;

using test::CommandResult;
using test::run_command;

std::string quote(const fs::path& p) {
  std::string out = "'";
  out += p.string();
  out += "'";
  return out;
}

CommandResult exao(const std::string& arguments) { return run_command(std::string(EXAO_BINARY) + " " + arguments); }

bool have(const std::string& tool) { return run_command("command -v " + tool).status == 0; }

// The Khronos validator (scripts/install-test-tools.sh), or why it cannot run.
std::string validator_missing() {
  if (run_command("node --version").status != 0) return "node is not installed: the glTF validator cannot run";
  if (!fs::exists(fs::path(EXAO_TEST_TOOLS) / "node_modules" / "gltf-validator")) {
    return std::string("the glTF validator is not installed: run scripts/install-test-tools.sh ") + EXAO_BUILD_DIR;
  }
  return "";
}

// Image files the input names but the shared scenes leave out (SOURCES.md): the output still
// names them, and the validator's IO_ERROR for them is the input's, not the bake's.
std::string missing_images(const fs::path& input) {
  if (input.extension() != ".gltf") return "";
  std::ifstream in(input);
  const std::string json((std::istreambuf_iterator<char>(in)), {});
  const std::regex uri("\"uri\"\\s*:\\s*\"([^\"]+)\"");
  std::string out;
  for (auto it = std::sregex_iterator(json.begin(), json.end(), uri); it != std::sregex_iterator(); ++it) {
    const std::string name = (*it)[1];
    if (name.rfind("data:", 0) != 0 && !fs::exists(input.parent_path() / name)) out += (out.empty() ? "" : ",") + name;
  }
  return out;
}

CommandResult validate(const fs::path& file, const fs::path& input = {}) {
  const std::string missing = input.empty() ? "" : missing_images(input);
  return run_command("node " + quote(EXAO_VALIDATE_SCRIPT) + " --modules " + quote(EXAO_TEST_TOOLS) +
             (missing.empty() ? "" : " --missing-ok '" + missing + "'") + " " + quote(file));
}

using test::BvhAo;

bool contains(const std::vector<std::string>& notes, const std::string& text) {
  return std::any_of(notes.begin(), notes.end(), [&](const std::string& n) { return n.find(text) != std::string::npos; });
}

std::string joined(const std::vector<std::string>& notes) {
  std::string out;
  for (const std::string& n : notes) out += n + "\n";
  return out;
}

tinygltf::Model load_model(const fs::path& path) {
  tinygltf::Model model;
  tinygltf::TinyGLTF context;
  context.SetImageLoader([](tinygltf::Image*, const int, std::string*, std::string*, int, int, const unsigned char*, int,
                            void*) { return true; },
                         nullptr);
  std::string err, warn;
  const bool ok = path.extension() == ".glb" ? context.LoadBinaryFromFile(&model, &err, &warn, path.string())
                                             : context.LoadASCIIFromFile(&model, &err, &warn, path.string());
  EXPECT_TRUE(ok) << err;
  return model;
}

bool listed(const std::vector<std::string>& list, const std::string& name) {
  return std::find(list.begin(), list.end(), name) != list.end();
}

// ---- --uv auto on the truck and the duck ---------------------------------------------------------

// CesiumMilkTruck's glass and window-trim primitives have every TEXCOORD_0 at one point: under
// --uv file their maps stay blank (and the bake says so); under auto they get a generated set,
// are told about, and hold AO.
TEST(UvAuto, TruckDegenerateUvPartsGetAo) {
  const fs::path path = test::real_scene("CesiumMilkTruck/glTF/CesiumMilkTruck.gltf");
  EXAO_REQUIRE_SCENE(path);
  const int size = 128;
  const auto bake_with = [&](bake::UvMode mode) {
    auto document = bake::Document::open(path.string());
    EXPECT_TRUE(document) << document.error().message;
    const BvhAo ao(document->scene(), 0.05f * document->scene().bounds().diagonal(), 32);
    bake::BakeOptions options;
    options.target = bake::Target::Texture;
    options.texture_size = size;
    options.uv = mode;
    auto result = bake::bake(*document, options, ao.function());
    EXPECT_TRUE(result) << result.error().message;
    return std::move(*result);
  };

  const bake::BakeResult file = bake_with(bake::UvMode::File);
  std::size_t blank = 0;
  for (const bake::AoMap& map : file.maps) blank += map.covered_texels == 0 ? 1 : 0;
  EXPECT_GT(blank, 0u) << "the truck's degenerate UVs were expected to leave a map blank under --uv file";
  EXPECT_TRUE(contains(file.notes, "covers no texel")) << joined(file.notes);  // never blank in silence

  const bake::BakeResult automatic = bake_with(bake::UvMode::Auto);
  EXPECT_TRUE(contains(automatic.notes, "covers no area")) << joined(automatic.notes);
  EXPECT_TRUE(contains(automatic.notes, "generated TEXCOORD_1")) << joined(automatic.notes);
  std::size_t generated_maps = 0;
  for (const bake::AoMap& map : automatic.maps) {
    EXPECT_GT(map.covered_texels, 0u) << "map " << map.label << " is blank";
    if (map.label.size() < 3 || map.label.substr(map.label.size() - 3) != "-uv") continue;
    ++generated_maps;
    // The trim sits in the cab's corners: its AO is well below open.
    double sum = 0.0;
    std::size_t n = 0;
    for (std::size_t i = 0; i < map.ao.size(); ++i) {
      if (map.filled[i] != 1) continue;
      sum += map.ao[i];
      ++n;
    }
    ASSERT_GT(n, 0u);
    std::printf("map %s: %zu texels, mean AO %.3f\n", map.label.c_str(), n, sum / static_cast<double>(n));
    EXPECT_LT(sum / static_cast<double>(n), 0.97) << map.label;
  }
  EXPECT_GT(generated_maps, 0u);

  // In the file: every occlusionTexture reads a set its primitives have, the generated ones
  // TEXCOORD_1, and the truck keeps its triangles.
  auto document = bake::Document::open(path.string());
  ASSERT_TRUE(document);
  const BvhAo ao(document->scene(), 0.05f * document->scene().bounds().diagonal(), 32);
  bake::BakeOptions options;
  options.target = bake::Target::Texture;
  options.texture_size = size;
  auto result = bake::bake(*document, options, ao.function());
  ASSERT_TRUE(result) << result.error().message;
  test::TempDir dir;
  std::vector<std::string> notes;
  ASSERT_TRUE(bake::save(*document, *result, {(dir / "truck.glb").string()}, notes));
  const tinygltf::Model model = load_model(dir / "truck.glb");
  std::size_t reading_set_1 = 0;
  for (const tinygltf::Mesh& mesh : model.meshes) {
    for (const tinygltf::Primitive& prim : mesh.primitives) {
      ASSERT_GE(prim.material, 0);
      const int set = model.materials[static_cast<std::size_t>(prim.material)].occlusionTexture.texCoord;
      EXPECT_GE(model.materials[static_cast<std::size_t>(prim.material)].occlusionTexture.index, 0);
      EXPECT_EQ(prim.attributes.count("TEXCOORD_" + std::to_string(set)), 1u) << mesh.name;
      reading_set_1 += set == 1 ? 1 : 0;
    }
  }
  EXPECT_GT(reading_set_1, 0u);
  auto reread = load_scene((dir / "truck.glb").string());
  ASSERT_TRUE(reread) << reread.error().message;
  EXPECT_EQ(reread->triangle_count(), document->scene().triangle_count());
}

// Texels where two triangles put surface points more than 10% of the diagonal apart (each
// triangle's point at the texel's centre, clamped into it): AO of unrelated surfaces averaged
// into one texel. Coverage is by 4 x 4 sample points per texel plus each corner's own texel, so
// that thin triangles count too.
std::size_t far_shared_texels(const bake::BakeResult& result, const bake::Document& document, int size) {
  const bake::ModelWalk& walk = document.impl().walk;
  const float far = 0.1f * document.scene().bounds().diagonal();
  std::size_t shared = 0;
  const auto n = static_cast<std::size_t>(size);
  for (std::size_t m = 0; m < result.maps.size(); ++m) {
    std::vector<glm::vec3> first(n * n, glm::vec3(NAN));
    std::vector<std::uint8_t> flagged(n * n, 0);
    for (std::size_t p = 0; p < walk.parts.size(); ++p) {
      if (result.part_map[p] != static_cast<int>(m)) continue;
      const std::vector<glm::vec2>& uv = result.part_corner_uv[p];
      for (std::size_t t = 0; t + 2 < uv.size(); t += 3) {
        const auto c = walk.corners(p, t / 3);
        const std::vector<glm::vec3>& w = walk.parts[p].world;
        const glm::dvec2 a = glm::dvec2(uv[t]) * double(size), b = glm::dvec2(uv[t + 1]) * double(size),
                         d = glm::dvec2(uv[t + 2]) * double(size);
        const double area = (b.x - a.x) * (d.y - a.y) - (d.x - a.x) * (b.y - a.y);
        std::set<std::size_t> texels;
        for (const glm::dvec2& corner : {a, b, d}) {
          texels.insert(std::min(n - 1, std::size_t(std::max(0.0, corner.y))) * n + std::min(n - 1, std::size_t(std::max(0.0, corner.x))));
        }
        const glm::dvec2 lo = glm::min(glm::min(a, b), d), hi = glm::max(glm::max(a, b), d);
        for (int y = std::max(0, int(lo.y)); y <= std::min(size - 1, int(hi.y)); ++y) {
          for (int x = std::max(0, int(lo.x)); x <= std::min(size - 1, int(hi.x)); ++x) {
            for (int k = 0; k < 16 && area != 0.0; ++k) {
              const glm::dvec2 s(x + (k % 4 + 0.5) / 4.0, y + (k / 4 + 0.5) / 4.0);
              const auto edge = [&](glm::dvec2 u, glm::dvec2 v) { return ((v.x - u.x) * (s.y - u.y) - (s.x - u.x) * (v.y - u.y)) * area; };
              if (edge(a, b) >= 0 && edge(b, d) >= 0 && edge(d, a) >= 0) {
                texels.insert(std::size_t(y) * n + std::size_t(x));
                break;
              }
            }
          }
        }
        // The surface point this triangle puts at texel i's centre (clamped into the triangle).
        const auto at = [&](std::size_t i) {
          const glm::dvec2 s(double(i % n) + 0.5, double(i / n) + 0.5);
          const auto edge = [&](glm::dvec2 u, glm::dvec2 v) { return (v.x - u.x) * (s.y - u.y) - (s.x - u.x) * (v.y - u.y); };
          glm::dvec3 bary(edge(b, d), edge(d, a), edge(a, b));
          if (area != 0.0) bary /= area;
          bary = glm::max(bary, glm::dvec3(0.0));
          const double sum = bary.x + bary.y + bary.z;
          bary = sum > 0.0 ? bary / sum : glm::dvec3(1.0 / 3.0);
          return glm::vec3(bary.x * glm::dvec3(w[c[0]]) + bary.y * glm::dvec3(w[c[1]]) + bary.z * glm::dvec3(w[c[2]]));
        };
        for (const std::size_t i : texels) {
          if (std::isnan(first[i].x)) {
            first[i] = at(i);
          } else if (!flagged[i] && glm::length(first[i] - at(i)) > far) {
            flagged[i] = 1;
            ++shared;
          }
        }
      }
    }
  }
  return shared;
}

// Duck's TEXCOORD_0 stacks distant parts of the model onto the same texels; under --uv auto the
// bake replaces it, and no texel is then shared by triangles far apart.
TEST(UvAuto, DuckHasNoTexelSharedByFarApartTriangles) {
  const fs::path path = test::real_scene("Duck/glTF-Binary/Duck.glb");
  EXAO_REQUIRE_SCENE(path);
  const int size = 512;
  const auto bake_with = [&](bake::UvMode mode, std::size_t& shared) {
    auto document = bake::Document::open(path.string());
    EXPECT_TRUE(document) << document.error().message;
    const BvhAo ao(document->scene(), 0.05f * document->scene().bounds().diagonal(), 32);
    bake::BakeOptions options;
    options.target = bake::Target::Texture;
    options.texture_size = size;
    options.texel_samples = 1;
    options.uv = mode;
    auto result = bake::bake(*document, options, ao.function());
    EXPECT_TRUE(result) << result.error().message;
    shared = far_shared_texels(*result, *document, size);
    return std::move(*result);
  };
  std::size_t shared_file = 0, shared_auto = 0;
  bake_with(bake::UvMode::File, shared_file);
  const bake::BakeResult automatic = bake_with(bake::UvMode::Auto, shared_auto);
  std::printf("texels shared by triangles > 10%% of the diagonal apart: file UVs %zu, --uv auto %zu\n", shared_file, shared_auto);
  EXPECT_GT(shared_file, 1000u) << "the measure should see Duck's stacked UVs";
  EXPECT_EQ(shared_auto, 0u);
  EXPECT_TRUE(contains(automatic.notes, "overlaps itself")) << joined(automatic.notes);
  EXPECT_EQ(automatic.maps.size(), 1u);
  EXPECT_EQ(automatic.maps[0].overlap_texels, 0u);
}

// ---- Quantised and transformed UVs ---------------------------------------------------------------

// Duck/glTF-Quantized stores TEXCOORD_0 as integers that its baseColorTexture's
// KHR_texture_transform maps into [0.026, 0.983]: laid out through that transform, the set is
// inside [0, 1], the map reads through the same transform, and the file passes the validator.
TEST(QuantizedUvs, DuckQuantizedBakesPerTexelAndValidates) {
  const fs::path path = test::real_scene("Duck/glTF-Quantized/Duck.gltf");
  EXAO_REQUIRE_SCENE(path);
  auto document = bake::Document::open(path.string());
  ASSERT_TRUE(document) << document.error().message;
  const BvhAo ao(document->scene(), 0.05f * document->scene().bounds().diagonal(), 32);
  bake::BakeOptions options;
  options.target = bake::Target::Texture;
  options.texture_size = 128;
  options.uv = bake::UvMode::File;
  auto result = bake::bake(*document, options, ao.function());
  ASSERT_TRUE(result) << result.error().message;
  EXPECT_TRUE(contains(result->notes, "through the KHR_texture_transform of its baseColorTexture")) << joined(result->notes);
  glm::vec2 lo(1e9f), hi(-1e9f);
  for (const auto& part : result->part_corner_uv) {
    for (const glm::vec2& t : part) {
      lo = glm::min(lo, t);
      hi = glm::max(hi, t);
    }
  }
  EXPECT_NEAR(lo.x, 0.026, 0.01);
  EXPECT_NEAR(hi.x, 0.983, 0.01);
  ASSERT_EQ(result->maps.size(), 1u);
  EXPECT_GT(result->maps[0].covered_texels, 1000u);

  test::TempDir dir;
  std::vector<std::string> notes;
  const fs::path out = dir / "duck-q.gltf";
  ASSERT_TRUE(bake::save(*document, *result, {out.string()}, notes));
  const tinygltf::Model model = load_model(out);
  ASSERT_EQ(model.materials.size(), 1u);
  const tinygltf::OcclusionTextureInfo& occlusion = model.materials[0].occlusionTexture;
  EXPECT_GE(occlusion.index, 0);
  EXPECT_EQ(occlusion.texCoord, 0);
  EXPECT_EQ(occlusion.extensions.count("KHR_texture_transform"), 1u);
  EXPECT_TRUE(listed(model.extensionsRequired, "KHR_mesh_quantization"));
  EXPECT_TRUE(listed(model.extensionsUsed, "KHR_texture_transform"));

  if (const std::string missing = validator_missing(); !missing.empty()) GTEST_SKIP() << missing;
  const CommandResult checked = validate(out, path);
  EXPECT_EQ(checked.status, 0) << checked.output;
  EXPECT_NE(checked.output.find(": 0 errors"), std::string::npos) << checked.output;
  // And through the command line with the default --uv auto.
  const fs::path cli_out = dir / "duck-q-auto.glb";
  const CommandResult baked = exao("bake " + quote(path) + " --texture 128 -n 32 --preview '' -o " + quote(cli_out));
  ASSERT_EQ(baked.status, 0) << baked.output;
  EXPECT_NE(baked.output.find("AO UVs of"), std::string::npos) << baked.output;
  const CommandResult checked_auto = validate(cli_out, path);
  EXPECT_NE(checked_auto.output.find(": 0 errors"), std::string::npos) << checked_auto.output;
}

// ---- Draco and meshopt ---------------------------------------------------------------------------

// Whether every triangle of `a` has one of `b` (with the same winding, any starting corner)
// within `tolerance`, one to one.
void expect_same_triangles(const Scene& a, const Scene& b, float tolerance, const std::string& what) {
  ASSERT_EQ(a.triangle_count(), b.triangle_count()) << what;
  const float cell = std::max(tolerance * 8.0f, 1e-3f * a.bounds().diagonal());
  const auto key = [&](const glm::vec3& c) {
    const glm::ivec3 k(glm::floor(c / cell));
    return (std::int64_t(k.x) * 73856093) ^ (std::int64_t(k.y) * 19349663) ^ (std::int64_t(k.z) * 83492791);
  };
  const auto centroid = [](const std::array<glm::vec3, 3>& t) { return (t[0] + t[1] + t[2]) / 3.0f; };
  std::unordered_multimap<std::int64_t, std::size_t> grid;
  for (std::size_t i = 0; i < b.triangle_count(); ++i) grid.emplace(key(centroid(b.triangle(i))), i);
  std::vector<bool> used(b.triangle_count(), false);
  std::size_t unmatched = 0;
  for (std::size_t i = 0; i < a.triangle_count(); ++i) {
    const auto ta = a.triangle(i);
    const glm::vec3 c = centroid(ta);
    bool found = false;
    for (int dz = -1; dz <= 1 && !found; ++dz) {
      for (int dy = -1; dy <= 1 && !found; ++dy) {
        for (int dx = -1; dx <= 1 && !found; ++dx) {
          const auto range = grid.equal_range(key(c + cell * glm::vec3(dx, dy, dz)));
          for (auto it = range.first; it != range.second && !found; ++it) {
            if (used[it->second]) continue;
            const auto tb = b.triangle(it->second);
            for (int r = 0; r < 3 && !found; ++r) {
              bool close = true;
              for (int k = 0; k < 3; ++k) close = close && glm::length(ta[k] - tb[(k + r) % 3]) <= tolerance;
              if (close) {
                found = true;
                used[it->second] = true;
              }
            }
          }
        }
      }
    }
    unmatched += found ? 0 : 1;
  }
  EXPECT_EQ(unmatched, 0u) << what << ": triangles without a match within " << tolerance;
}

class Compressed : public ::testing::Test {
 protected:
  void SetUp() override {
    for (const char* tool : {"draco_transcoder", "gltfpack"}) {
      if (!have(tool)) GTEST_SKIP() << tool << " is not installed (scripts/install-deps.sh installs draco and gltfpack)";
    }
  }
  test::TempDir dir;
};

TEST_F(Compressed, DracoAndMeshoptLoadTheSameTrianglesAsTheirSource) {
  struct Case {
    std::string source, tool, options, output;
    float tolerance;  // of the diagonal: 0 for lossless settings
  };
  const std::vector<Case> cases = {
      {"Box/glTF-Binary/Box.glb", "draco_transcoder", "-qp 0 -qn 0", "box-draco.glb", 0.0f},
      {"Duck/glTF-Binary/Duck.glb", "draco_transcoder", "-qp 0 -qt 0 -qn 0", "duck-draco.glb", 0.0f},
      // Draco's defaults quantise positions to 11 bits: within a step of 1/2047 of the extent.
      {"Duck/glTF-Binary/Duck.glb", "draco_transcoder", "", "duck-draco-q.glb", 1e-3f},
      {"Box/glTF-Binary/Box.glb", "gltfpack", "-c -noq", "box-meshopt.glb", 1e-6f},
      {"Duck/glTF-Binary/Duck.glb", "gltfpack", "-c -noq", "duck-meshopt.glb", 1e-6f},
      // gltfpack's defaults quantise (KHR_mesh_quantization) to 14 bits and filter normals.
      {"Duck/glTF-Binary/Duck.glb", "gltfpack", "-cc", "duck-meshopt-q.glb", 1e-3f},
      {"CesiumMilkTruck/glTF/CesiumMilkTruck.gltf", "gltfpack", "-c -noq", "truck-meshopt.gltf", 1e-6f},
  };
  std::size_t tested = 0;
  for (const Case& c : cases) {
    const fs::path source = test::real_scene(c.source);
    if (source.empty()) continue;
    const fs::path out = dir / c.output;
    const std::string command = c.tool + " " + c.options + " -i " + quote(source) + " -o " + quote(out);
    const CommandResult made = run_command(command);
    ASSERT_EQ(made.status, 0) << command << "\n" << made.output;
    std::ifstream in(out, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), {});
    const std::string extension = c.tool == "gltfpack" ? "EXT_meshopt_compression" : "KHR_draco_mesh_compression";
    ASSERT_NE(bytes.find(extension), std::string::npos) << c.output << " does not use " << extension;

    auto original = load_scene(source.string());
    auto compressed = load_scene(out.string());
    ASSERT_TRUE(original) << original.error().message;
    ASSERT_TRUE(compressed) << compressed.error().message;
    EXPECT_TRUE(std::any_of(compressed->report.notes.begin(), compressed->report.notes.end(),
                            [&](const std::string& n) { return n.find(extension) != std::string::npos; }));
    const float diagonal = original->bounds().diagonal();
    expect_same_triangles(*original, *compressed, std::max(c.tolerance * diagonal, 1e-6f * diagonal), c.output);
    ++tested;
  }
  if (tested == 0) GTEST_SKIP() << "real scenes not found (set EXAO_SCENES_DIR)";

  // KHR_meshopt_compression (the ratified successor) reads the same streams: gltfpack 0.18 only
  // writes EXT_, so the extension is renamed in a .gltf it wrote.
  const fs::path box = test::real_scene("Box/glTF-Binary/Box.glb");
  ASSERT_EQ(run_command("gltfpack -c -noq -i " + quote(box) + " -o " + quote(dir / "box-ext.gltf")).status, 0);
  std::ifstream in(dir / "box-ext.gltf");
  std::string json((std::istreambuf_iterator<char>(in)), {});
  for (std::size_t at = json.find("EXT_meshopt_compression"); at != std::string::npos; at = json.find("EXT_meshopt_compression")) {
    json.replace(at, 3, "KHR");
  }
  test::write_file(dir / "box-khr.gltf", json);
  fs::copy_file(dir / "box-ext.bin", dir / "box-khr.bin");
  auto khr = load_scene((dir / "box-khr.gltf").string());
  ASSERT_TRUE(khr) << khr.error().message;
  EXPECT_TRUE(contains(khr->report.notes, "KHR_meshopt_compression")) << joined(khr->report.notes);
  expect_same_triangles(*load_scene(box.string()), *khr, 1e-6f, "box-khr.gltf");
}

// Every command reads them, and a bake writes them uncompressed, without the extension, valid.
TEST_F(Compressed, EveryCommandReadsThemAndABakeWritesThemPlain) {
  const fs::path source = test::real_scene("Duck/glTF-Binary/Duck.glb");
  EXAO_REQUIRE_SCENE(source);
  for (const auto& [tool, options, name] :
       std::vector<std::array<std::string, 3>>{{"draco_transcoder", "", "duck-draco.glb"}, {"gltfpack", "-c", "duck-meshopt.glb"}}) {
    const fs::path packed = dir / name;
    ASSERT_EQ(run_command(tool + " " + options + " -i " + quote(source) + " -o " + quote(packed)).status, 0);
    const CommandResult info = exao("info " + quote(packed));
    EXPECT_EQ(info.status, 0) << info.output;
    EXPECT_NE(info.output.find("4212"), std::string::npos) << info.output;  // Duck's triangles
    const CommandResult render = exao("render " + quote(packed) + " -W 32 -H 24 -n 32 -o " + quote(dir / (name + ".exr")));
    EXPECT_EQ(render.status, 0) << render.output;
    test::write_file(dir / "points.txt", "0 0 0 0 1 0\n");
    const CommandResult query = exao("query " + quote(packed) + " -n 32 --points " + quote(dir / "points.txt") + " -o " +
                                     quote(dir / (name + ".txt")));
    EXPECT_EQ(query.status, 0) << query.output;
    for (const std::string& bake_options : {std::string("--vertex"), std::string("--texture 128")}) {
      const fs::path out = dir / (name + (bake_options == "--vertex" ? "-v.glb" : "-t.gltf"));
      const CommandResult baked = exao("bake " + quote(packed) + " " + bake_options + " -n 32 --preview '' -o " + quote(out));
      ASSERT_EQ(baked.status, 0) << baked.output;
      EXPECT_NE(baked.output.find("a bake writes them uncompressed"), std::string::npos) << baked.output;
      const tinygltf::Model model = load_model(out);
      for (const char* ext : {"KHR_draco_mesh_compression", "EXT_meshopt_compression"}) {
        EXPECT_FALSE(listed(model.extensionsUsed, ext)) << out;
        EXPECT_FALSE(listed(model.extensionsRequired, ext)) << out;
      }
      auto reread = load_scene(out.string());
      ASSERT_TRUE(reread) << reread.error().message;
      EXPECT_EQ(reread->triangle_count(), 4212u);
      if (validator_missing().empty()) {
        const CommandResult checked = validate(out);
        EXPECT_NE(checked.output.find(": 0 errors"), std::string::npos) << out << "\n" << checked.output;
      }
    }
  }
}

// ---- The ground plane ----------------------------------------------------------------------------

// Box (a unit cube) standing on the plane: the corners of its side faces at the bottom lose the
// rays that go down, the top does not change, no receiver lies on the plane, and the plane is in
// no output.
TEST(Ground, DarkensTheUndersideContactAndIsNeverWritten) {
  const fs::path path = test::real_scene("Box/glTF-Binary/Box.glb");
  EXAO_REQUIRE_SCENE(path);
  struct Baked {
    std::vector<Receiver> receivers;
    std::vector<float> ao;
    std::vector<std::string> notes;
    fs::path output;
  };
  test::TempDir dir;
  const auto bake_with = [&](bool ground) {
    bake::ConvertOptions convert;
    convert.ground = ground;
    auto document = bake::Document::open(path.string(), convert);
    EXPECT_TRUE(document) << document.error().message;
    const Scene& scene = document->scene();
    EXPECT_EQ(scene.triangle_count(), ground ? 14u : 12u);
    // The diagonal (and so "5%") stays the model's.
    EXPECT_NEAR(scene.bounds().diagonal(), std::sqrt(3.0f), 1e-5f);
    const BvhAo ao(scene, 0.2f, 64);
    bake::BakeOptions options;
    auto result = bake::bake(*document, options, ao.function());
    EXPECT_TRUE(result) << result.error().message;
    Baked out{result->receivers, result->ao, document->notes(), dir / (ground ? "ground.glb" : "plain.glb")};
    std::vector<std::string> notes;
    EXPECT_TRUE(bake::save(*document, *result, {out.output.string()}, notes));
    return out;
  };
  const Baked plain = bake_with(false), ground = bake_with(true);
  ASSERT_EQ(plain.receivers.size(), ground.receivers.size());
  EXPECT_TRUE(contains(ground.notes, "ground plane at y = -0.5")) << joined(ground.notes);
  double bottom_plain = 0.0, bottom_ground = 0.0;
  std::size_t bottom = 0;
  for (std::size_t i = 0; i < plain.receivers.size(); ++i) {
    const Receiver& r = ground.receivers[i];
    EXPECT_GE(r.position.y, -0.5f - 1e-6f);  // every receiver is on the box
    if (r.position.y > 0.4f) {
      EXPECT_EQ(plain.ao[i], ground.ao[i]) << "top vertex " << i;
    }
    if (r.position.y < -0.4f && std::abs(r.normal.y) < 0.1f) {  // a side face's bottom corner
      bottom_plain += plain.ao[i];
      bottom_ground += ground.ao[i];
      ++bottom;
    }
  }
  ASSERT_GT(bottom, 0u);
  bottom_plain /= double(bottom);
  bottom_ground /= double(bottom);
  std::printf("side faces' bottom corners: AO %.3f without the plane, %.3f with it\n", bottom_plain, bottom_ground);
  EXPECT_GT(bottom_plain, 0.95);
  EXPECT_LT(bottom_ground, bottom_plain - 0.25);
  // The plane is in no output: the baked file holds the box's triangles, at the box's bounds.
  auto reread = load_scene(ground.output.string());
  ASSERT_TRUE(reread) << reread.error().message;
  EXPECT_EQ(reread->triangle_count(), 12u);
  EXPECT_NEAR(reread->bounds().diagonal(), std::sqrt(3.0f), 1e-5f);
  // And through the command line, with an explicit height.
  const CommandResult baked = exao("bake " + quote(path) + " --ground -0.5 -n 32 --preview '' -o " + quote(dir / "cli.glb"));
  EXPECT_EQ(baked.status, 0) << baked.output;
  EXPECT_NE(baked.output.find("ground plane at y = -0.5"), std::string::npos) << baked.output;
  const CommandResult bad = exao("bake " + quote(path) + " --ground sideways -o " + quote(dir / "bad.glb"));
  EXPECT_NE(bad.status, 0);
  EXPECT_NE(bad.output.find("--ground"), std::string::npos) << bad.output;
}

}  // namespace
}  // namespace exao
