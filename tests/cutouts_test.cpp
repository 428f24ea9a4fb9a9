// Cut-outs (core/cutouts.h, issue 24): alpha-tested occluders give Embree-with-the-filter's answer
// on 100% of rays in auto (every split, every instruction set), bvh == brute bit for bit at every
// instruction set, on a generated foliage scene (checker cards over a ground) and on the real
// AlphaBlendModeTest; an opaque-everywhere texture is the opaque answer bit for bit, a fully
// transparent card blocks nothing, a hole lets exactly the rays through that cross it; bad images
// and UVs fall back with a note.

#include <gtest/gtest.h>
#include <png.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "bake/bake.h"
#include "bake/document.h"
#include "core/builtin_scenes.h"
#include "core/cutouts.h"
#include "core/isa.h"
#include "io/load_scene.h"
#include "engine/engine.h"
#include "engine/geometry.h"
#include "tests/test_support.h"

namespace exao {
namespace {

using engine::Method;

MaskSet run(const Scene& scene, engine::Options o, std::span<const Receiver> receivers) {
  Result<engine::Engine> e = engine::Engine::build(scene, o, engine::Receivers::Points);
  EXPECT_TRUE(e) << (e ? "" : e.error().message);
  if (!e) return {};
  Result<MaskSet> m = e->masks(receivers);
  EXPECT_TRUE(m);
  return m ? std::move(*m) : MaskSet{};
}

std::uint64_t differing_rays(const MaskSet& a, const MaskSet& b) {
  EXPECT_EQ(a.size(), b.size());
  std::uint64_t rays = 0;
  for (std::size_t i = 0; i < a.size() && i < b.size(); ++i) {
    for (std::size_t w = 0; w < a.row(i).size(); ++w) rays += std::popcount(a.row(i)[w] ^ b.row(i)[w]);
  }
  return rays;
}

std::uint64_t blocked_rays(const MaskSet& m) {
  std::uint64_t n = 0;
  for (std::size_t i = 0; i < m.size(); ++i) n += m.blocked_count(i);
  return n;
}

// The pixels of `camera` (what `exao render` computes AO at), every `stride`-th.
std::vector<Receiver> pixels(const Scene& scene, const Camera& camera, int width, int height) {
  engine::Options o;
  o.method = Method::Embree;
  Result<engine::Engine> e = engine::Engine::build(scene, o, engine::Receivers::Pixels);
  EXPECT_TRUE(e) << (e ? "" : e.error().message);
  if (!e) return {};
  Result<PixelReceivers> p = e->pixel_receivers(camera, width, height);
  EXPECT_TRUE(p);
  return p ? p->receivers : std::vector<Receiver>{};
}

// auto (each split; masks to the end at every instruction set) == Embree on every ray; bvh ==
// brute at every instruction set; returns the rays where bvh differs from Embree (grazing only).
std::uint64_t expect_exact(const Scene& scene, engine::Options o, std::span<const Receiver> receivers) {
  o.method = Method::Embree;
  const MaskSet reference = run(scene, o, receivers);
  EXPECT_GT(blocked_rays(reference), 0u) << "nothing occluded proves nothing";
  o.method = Method::Auto;
  for (const bvh::HybridPolicy policy : {bvh::HybridPolicy::Adaptive, bvh::HybridPolicy::Masks, bvh::HybridPolicy::Rays}) {
    o.hybrid = policy;
    std::vector<std::optional<Isa>> isas{std::nullopt};
    if (policy == bvh::HybridPolicy::Masks) {
      for (const Isa isa : supported_isas()) isas.push_back(isa);
    }
    for (const std::optional<Isa>& isa : isas) {
      o.isa = isa;
      EXPECT_EQ(differing_rays(run(scene, o, receivers), reference), 0u)
          << "auto, " << bvh::hybrid_policy_name(policy) << ", " << (isa ? isa_name(*isa) : "default");
    }
  }
  o.method = Method::Brute;
  o.isa.reset();
  const MaskSet brute = run(scene, o, receivers);
  o.method = Method::Bvh;
  for (const Isa isa : supported_isas()) {
    o.isa = isa;
    EXPECT_EQ(differing_rays(run(scene, o, receivers), brute), 0u) << "bvh vs brute, " << isa_name(isa);
  }
  return differing_rays(brute, reference);
}

engine::Options at(float percent) {
  engine::Options o;
  o.radius = engine::Length{percent, true};
  o.samples = 128;
  return o;
}

TEST(Cutouts, FoliageIsEmbreeWithTheFilterOnEveryRay) {
  const Scene scene = make_foliage();
  ASSERT_TRUE(scene.cutouts);
  const std::vector<Receiver> receivers = pixels(scene, scene.cameras.at(0), 96, 72);
  ASSERT_GT(receivers.size(), 3000u);
  const std::uint64_t grazing = expect_exact(scene, at(5.0f), receivers);
  EXPECT_EQ(grazing, 0u) << "bvh alone vs Embree";
  // The cut-outs matter: the opaque cards block more.
  engine::Options o = at(5.0f);
  o.method = Method::Embree;
  const MaskSet cut = run(scene, o, receivers);
  o.cutouts.enabled = false;
  const MaskSet opaque = run(scene, o, receivers);
  EXPECT_LT(blocked_rays(cut), blocked_rays(opaque) * 9 / 10);
  EXPECT_EQ(differing_rays(opaque, run(make_foliage(false), o, receivers)), 0u) << "cutouts off == no cut-outs";
  std::cout << "  foliage: " << receivers.size() << " pixels, " << blocked_rays(cut) << " rays blocked with cut-outs, "
            << blocked_rays(opaque) << " with opaque cards\n";
}

TEST(Cutouts, StochasticBlendIsEmbreeOnEveryRay) {
  Scene scene = make_foliage();
  auto blended = std::make_shared<Cutouts>(*scene.cutouts);
  blended->materials[0].blend = true;
  scene.cutouts = blended;
  const std::vector<Receiver> receivers = pixels(scene, scene.cameras.at(0), 64, 48);
  engine::Options o = at(5.0f);
  o.cutouts.blend = BlendRule::Stochastic;
  expect_exact(scene, o, receivers);
  // BLEND is opaque by default: the same bits as the opaque cards.
  o = at(5.0f);
  o.method = Method::Embree;
  EXPECT_EQ(differing_rays(run(scene, o, receivers), run(make_foliage(false), o, receivers)), 0u);
}

// The bakes see the cut-outs: the document of a built-in scene (converted to glTF) and of a glTF
// file carry them, and its vertex and texel receivers are Embree's answer.
TEST(Cutouts, BakeReceiversAreEmbreeWithTheFilter) {
  std::vector<std::string> inputs{"foliage"};
  const auto real = test::real_scene("AlphaBlendModeTest/glTF/AlphaBlendModeTest.gltf");
  if (!real.empty()) inputs.push_back(real.string());
  for (const std::string& input : inputs) {
    SCOPED_TRACE(input);
    Result<bake::Document> doc = bake::Document::open(input);
    ASSERT_TRUE(doc) << doc.error().message;
    ASSERT_TRUE(doc->scene().cutouts);
    EXPECT_GT(doc->scene().cutouts->tested_count(), 0u);
    for (const bake::Target target : {bake::Target::Vertex, bake::Target::Texture}) {
      bake::BakeOptions options;
      options.target = target;
      options.texture_size = 256;
      Result<std::vector<Receiver>> all = bake::bake_receivers(*doc, options);
      ASSERT_TRUE(all) << all.error().message;
      // At most ~3000 of them, spread over the whole model: enough, and fast.
      auto receivers = std::make_unique<std::vector<Receiver>>();
      const std::size_t stride = std::max<std::size_t>(1, all->size() / 3000);
      for (std::size_t i = 0; i < all->size(); i += stride) receivers->push_back((*all)[i]);
      engine::Options o = at(5.0f);
      o.method = Method::Embree;
      const MaskSet reference = run(doc->scene(), o, *receivers);
      EXPECT_GT(blocked_rays(reference), 0u);
      o.method = Method::Auto;
      EXPECT_EQ(differing_rays(run(doc->scene(), o, *receivers), reference), 0u);
      o.method = Method::Embree;
      o.cutouts.enabled = false;
      EXPECT_NE(differing_rays(run(doc->scene(), o, *receivers), reference), 0u) << "the cut-outs change the bake";
    }
  }
}

// One horizontal card 1 above a ground plane, a texture of its own (nearest filtering), and
// receivers on the ground below it.
struct CardScene {
  Scene scene;
  std::vector<Receiver> receivers;
};

CardScene card_over_ground(std::shared_ptr<AlphaTexture> texture) {
  CardScene c;
  c.scene.name = "card";
  c.scene.add_triangle({-4, 0, 4}, {4, 0, 4}, {4, 0, -4}, false, 0);
  c.scene.add_triangle({-4, 0, 4}, {4, 0, -4}, {-4, 0, -4}, false, 0);
  auto cutouts = std::make_shared<Cutouts>();
  cutouts->of_triangle.assign(2, -1);
  if (texture) cutouts->textures.push_back(std::move(texture));
  CutoutMaterial m;
  m.texture = cutouts->textures.empty() ? -1 : 0;
  m.factor = cutouts->textures.empty() ? 0.0f : 1.0f;  // no texture: a fully transparent card
  cutouts->materials.push_back(m);
  // a = (-1, 1, 1), b = (1, 1, 1), d = (-1, 1, -1): UV (0, 1) at a, (1, 1) at b, (0, 0) at d.
  add_cutout_quad(c.scene, *cutouts, {-1, 1, 1}, {1, 1, 1}, {-1, 1, -1}, 0, true);
  c.scene.cutouts = cutouts;
  for (int i = 0; i < 5; ++i) {
    for (int j = 0; j < 5; ++j) {
      c.receivers.push_back({{-0.4f + 0.2f * static_cast<float>(i), 0.0f, -0.4f + 0.2f * static_cast<float>(j)}, {0, 1, 0}, static_cast<std::uint64_t>(5 * i + j)});
    }
  }
  return c;
}

std::shared_ptr<AlphaTexture> uniform_texture(std::uint16_t alpha) {
  auto t = std::make_shared<AlphaTexture>();
  t->width = t->height = 8;
  t->filter = TextureFilter::Nearest;
  t->alpha.assign(64, alpha);
  return t;
}

TEST(Cutouts, OpaqueTextureIsTheOpaqueAnswerBitForBit) {
  CardScene c = card_over_ground(uniform_texture(65535));
  Scene opaque = c.scene;
  opaque.cutouts = nullptr;
  engine::Options o;
  o.radius = {2.0f, false};
  for (const Method m : {Method::Embree, Method::Brute, Method::Bvh, Method::Auto}) {
    o.method = m;
    const MaskSet with = run(c.scene, o, c.receivers);
    EXPECT_GT(blocked_rays(with), 0u);
    EXPECT_EQ(differing_rays(with, run(opaque, o, c.receivers)), 0u) << engine::method_name(m);
  }
}

TEST(Cutouts, TransparentCardBlocksNothing) {
  for (const bool textured : {true, false}) {
    CardScene c = card_over_ground(textured ? uniform_texture(0) : nullptr);
    engine::Options o;
    o.radius = {2.0f, false};
    for (const Method m : {Method::Embree, Method::Brute, Method::Bvh, Method::Auto}) {
      o.method = m;
      EXPECT_EQ(blocked_rays(run(c.scene, o, c.receivers)), 0u) << engine::method_name(m) << (textured ? " texture 0" : " factor 0");
      o.cutouts.enabled = false;
      EXPECT_GT(blocked_rays(run(c.scene, o, c.receivers)), 0u) << "cutouts off: the card is opaque";
      o.cutouts.enabled = true;
    }
  }
}

TEST(Cutouts, AHoleLetsThroughExactlyTheRaysThatCrossIt) {
  // 8 x 8 texels, the middle 4 x 4 open: the card's hole is x, z in (-0.5, 0.5).
  auto texture = uniform_texture(65535);
  for (int y = 2; y < 6; ++y) {
    for (int x = 2; x < 6; ++x) texture->alpha[static_cast<std::size_t>(8 * y + x)] = 0;
  }
  CardScene c = card_over_ground(texture);
  engine::Options o;
  o.radius = {2.0f, false};
  o.origin_offset = 0.0f;
  o.method = Method::Embree;
  Result<engine::Engine> e = engine::Engine::build(c.scene, o, engine::Receivers::Points);
  ASSERT_TRUE(e);
  const ShadowRays& rays = e->rays();
  std::size_t checked = 0, through = 0;
  for (const Method m : {Method::Embree, Method::Brute, Method::Bvh, Method::Auto}) {
    o.method = m;
    const MaskSet masks = run(c.scene, o, c.receivers);
    for (std::size_t r = 0; r < c.receivers.size(); ++r) {
      const Frame frame = rays.frame(c.receivers[r]);
      for (int i = 0; i < rays.count(); ++i) {
        const glm::vec3 d = rays.world_direction(frame, i);
        const float s = (1.0f - frame.origin.y) / d.y;  // where the ray meets the card's plane y = 1
        const glm::vec3 hit = frame.origin + s * d;
        if (!(s <= rays.radius * rays.pattern.lengths[static_cast<std::size_t>(i)] * 0.999f)) continue;  // ends short
        const float edge = std::min({std::abs(std::abs(hit.x) - 0.5f), std::abs(std::abs(hit.z) - 0.5f),
                                     std::abs(std::abs(hit.x) - 1.0f), std::abs(std::abs(hit.z) - 1.0f)});
        if (edge < 1e-3f) continue;  // on a texel or card edge: either answer is defensible
        const bool on_card = std::abs(hit.x) < 1.0f && std::abs(hit.z) < 1.0f;
        const bool in_hole = std::abs(hit.x) < 0.5f && std::abs(hit.z) < 0.5f;
        const bool blocked = (masks.row(r)[static_cast<std::size_t>(i / 64)] >> (i % 64)) & 1u;
        EXPECT_EQ(blocked, on_card && !in_hole) << engine::method_name(m) << " receiver " << r << " ray " << i;
        ++checked;
        through += in_hole;
      }
    }
  }
  EXPECT_GT(through, 100u) << "rays through the hole";
  EXPECT_GT(checked, 1000u);
}

TEST(Cutouts, AlphaBlendModeTestIsEmbreeWithTheFilterOnEveryRay) {
  const auto path = test::real_scene("AlphaBlendModeTest/glTF/AlphaBlendModeTest.gltf");
  EXAO_REQUIRE_SCENE(path);
  Result<Scene> scene = load_scene(path.string());
  ASSERT_TRUE(scene) << scene.error().message;
  ASSERT_TRUE(scene->cutouts) << "its MASK quads read AlphaBlendLabels.png";
  ASSERT_EQ(scene->cutouts->textures.size(), 1u);
  EXPECT_EQ(scene->cutouts->textures[0]->width, 1024);
  EXPECT_GT(scene->cutouts->tested_count(), 0u);
  // Three MASK materials, one BLEND.
  int mask = 0, blend = 0;
  for (const CutoutMaterial& m : scene->cutouts->materials) (m.blend ? blend : mask) += 1;
  EXPECT_EQ(mask, 3);
  EXPECT_EQ(blend, 1);
  const Bounds b = scene->bounds();
  const glm::vec3 centre = 0.5f * (b.lo + b.hi);
  const Camera camera = look_at(centre + glm::vec3(0.0f, 0.2f, 1.0f) * b.diagonal(), centre, 50.0f);
  const std::vector<Receiver> receivers = pixels(*scene, camera, 96, 72);
  engine::Options o = at(5.0f);
  const std::uint64_t grazing = expect_exact(*scene, o, receivers);
  o.cutouts.blend = BlendRule::Stochastic;
  expect_exact(*scene, o, receivers);
  o.cutouts.blend = BlendRule::Cutoff;
  o.cutouts.blend_cutoff = 0.3f;
  expect_exact(*scene, o, receivers);
  std::cout << "  AlphaBlendModeTest: " << receivers.size() << " pixels; bvh alone differs from Embree on " << grazing
            << " rays\n";
}

// ---- glTF loading and bad input ---------------------------------------------------------------

// A two-triangle quad (z = 0, facing +z) with TEXCOORD_0, material 0 as `material_json`, and
// `images_json`/`textures_json`; written as .gltf + .bin in `dir`.
std::string write_quad(const test::TempDir& dir, const std::string& material_json, const std::string& images_json,
                       const std::vector<float>& uv = {0, 1, 1, 1, 1, 0, 0, 0}) {
  const float positions[] = {-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0};
  const std::uint16_t indices[] = {0, 1, 2, 0, 2, 3};
  std::string bin(reinterpret_cast<const char*>(positions), sizeof positions);
  bin.append(reinterpret_cast<const char*>(uv.data()), uv.size() * sizeof(float));
  bin.append(reinterpret_cast<const char*>(indices), sizeof indices);
  test::write_file(dir / "quad.bin", bin);
  const std::string json = R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],
"meshes":[{"primitives":[{"attributes":{"POSITION":0,"TEXCOORD_0":1},"indices":2,"material":0}]}],
"buffers":[{"uri":"quad.bin","byteLength":92}],
"bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":48},{"buffer":0,"byteOffset":48,"byteLength":32},{"buffer":0,"byteOffset":80,"byteLength":12}],
"accessors":[{"bufferView":0,"componentType":5126,"count":4,"type":"VEC3","min":[-1,-1,0],"max":[1,1,0]},
{"bufferView":1,"componentType":5126,"count":4,"type":"VEC2"},{"bufferView":2,"componentType":5123,"count":6,"type":"SCALAR"}],
"materials":[)" + material_json + "]" + images_json + "}";
  test::write_file(dir / "quad.gltf", json);
  return (dir / "quad.gltf").string();
}

const std::string kMask = R"({"alphaMode":"MASK","pbrMetallicRoughness":{"baseColorTexture":{"index":0}}})";
const std::string kTexture = R"(,"textures":[{"source":0,"sampler":0}],"samplers":[{"magFilter":9728}],"images":[{"uri":"alpha.png"}])";

bool has_note(const Scene& scene, const std::string& text) {
  for (const std::string& n : scene.report.notes) {
    if (n.find(text) != std::string::npos) return true;
  }
  return false;
}

// A 2 x 2 RGBA PNG: alpha 0 in its top-left texel, 255 elsewhere.
std::string alpha_png() {
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  image.width = 2;
  image.height = 2;
  image.format = PNG_FORMAT_RGBA;
  const unsigned char pixels[16] = {255, 255, 255, 0, 255, 255, 255, 255, 255, 255, 255, 255, 255, 255, 255, 255};
  png_alloc_size_t size = 0;
  EXPECT_TRUE(png_image_write_to_memory(&image, nullptr, &size, 0, pixels, 0, nullptr));
  std::string out(size, '\0');
  EXPECT_TRUE(png_image_write_to_memory(&image, out.data(), &size, 0, pixels, 0, nullptr));
  out.resize(size);
  return out;
}

TEST(CutoutsLoading, ReadsTheAlphaOfAPngTexture) {
  test::TempDir dir;
  test::write_file(dir / "alpha.png", alpha_png());
  Result<Scene> scene = load_scene(write_quad(dir, kMask, kTexture));
  ASSERT_TRUE(scene) << scene.error().message;
  ASSERT_TRUE(scene->cutouts);
  ASSERT_EQ(scene->cutouts->textures.size(), 1u);
  const AlphaTexture& t = *scene->cutouts->textures[0];
  EXPECT_EQ(t.filter, TextureFilter::Nearest);
  EXPECT_EQ(t.sample(0.25, 0.25), 0.0);  // the top-left texel (v = 0 is the image's first row)
  EXPECT_EQ(t.sample(0.75, 0.25), 1.0);
  EXPECT_EQ(scene->cutouts->tested_count(), 2u);
  // UV (0, 0) is the quad's corner (-1, 1, 0): a ray down at (-0.5, 0.5) meets the open texel.
  EXPECT_FALSE(scene->cutouts->blocks(0, {-0.5f, 0.5f, 1.0f}, {0, 0, -1}) && scene->cutouts->blocks(1, {-0.5f, 0.5f, 1.0f}, {0, 0, -1}));
  EXPECT_TRUE(scene->cutouts->blocks(0, {0.5f, -0.5f, 1.0f}, {0, 0, -1}));
}

TEST(CutoutsLoading, BadImagesAndUvsFallBackWithANote) {
  {
    test::TempDir dir;  // no alpha.png beside the file
    Result<Scene> scene = load_scene(write_quad(dir, kMask, kTexture));
    ASSERT_TRUE(scene) << scene.error().message;
    EXPECT_TRUE(has_note(*scene, "'alpha.png' is missing"));
    EXPECT_FALSE(scene->cutouts && scene->cutouts->any() && scene->cutouts->textures.size() > 0);
  }
  {
    test::TempDir dir;
    test::write_file(dir / "alpha.png", "not an image at all");
    Result<Scene> scene = load_scene(write_quad(dir, kMask, kTexture));
    ASSERT_TRUE(scene);
    EXPECT_TRUE(has_note(*scene, "is not a PNG or JPEG"));
  }
  {
    test::TempDir dir;  // a PNG header claiming 100000 x 100000 texels: never decoded
    std::string png = alpha_png();
    const unsigned char huge[8] = {0, 1, 0x86, 0xA0, 0, 1, 0x86, 0xA0};
    png.replace(16, 8, reinterpret_cast<const char*>(huge), 8);
    test::write_file(dir / "alpha.png", png);
    Result<Scene> scene = load_scene(write_quad(dir, kMask, kTexture));
    ASSERT_TRUE(scene);
    EXPECT_TRUE(has_note(*scene, "100000 x 100000 texels, beyond the limit"));
  }
  {
    test::TempDir dir;  // a texCoord set the primitive does not have
    test::write_file(dir / "alpha.png", alpha_png());
    const std::string material = R"({"alphaMode":"MASK","pbrMetallicRoughness":{"baseColorTexture":{"index":0,"texCoord":3}}})";
    Result<Scene> scene = load_scene(write_quad(dir, material, kTexture));
    ASSERT_TRUE(scene);
    EXPECT_TRUE(has_note(*scene, "TEXCOORD_3, which it does not have"));
    EXPECT_FALSE(scene->cutouts && scene->cutouts->any());
  }
  {
    test::TempDir dir;  // a NaN UV on one corner: the triangles that use it are opaque
    test::write_file(dir / "alpha.png", alpha_png());
    Result<Scene> scene = load_scene(write_quad(dir, kMask, kTexture, {0, 1, 1, 1, std::nanf(""), 0, 0, 0}));
    ASSERT_TRUE(scene);
    EXPECT_TRUE(has_note(*scene, "NaN or infinite UV"));
    EXPECT_FALSE(scene->cutouts && scene->cutouts->any());
  }
}

}  // namespace
}  // namespace exao

namespace exao {
namespace {

TEST(CutoutsCli, InfoListsTheAlphaTestedMaterials) {
  const test::CommandResult run = test::run_exao(EXAO_BINARY, "info foliage");
  EXPECT_EQ(run.status, 0) << run.output;
  EXPECT_NE(run.output.find("cut-outs     98 triangles alpha-tested"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("checker-cards: MASK"), std::string::npos) << run.output;
  const test::CommandResult off = test::run_exao(EXAO_BINARY, "info foliage --cutouts off");
  EXPECT_NE(off.output.find("cut-outs     0 triangles alpha-tested (cut-outs off"), std::string::npos) << off.output;
}

TEST(CutoutsCli, RasterAndBadBlendOptionsAreRefusedInOneLine) {
  test::TempDir dir;
  const std::string out = " -W 32 -o " + (dir / "a.exr").string() + " --png ''";
  test::expect_one_line_error(test::run_exao(EXAO_BINARY, "render foliage --method raster" + out), "--method");
  test::expect_one_line_error(test::run_exao(EXAO_BINARY, "render foliage --blend cutoff" + out), "--blend");
  test::expect_one_line_error(test::run_exao(EXAO_BINARY, "render foliage --blend cutoff 2" + out), "--blend");
  test::expect_one_line_error(test::run_exao(EXAO_BINARY, "render foliage --blend sometimes" + out), "--blend");
  EXPECT_FALSE(std::filesystem::exists(dir / "a.exr")) << "refused before any work";
  const test::CommandResult raster = test::run_exao(EXAO_BINARY, "render foliage --method raster --cutouts off" + out);
  EXPECT_EQ(raster.status, 0) << raster.output;
}

}  // namespace
}  // namespace exao
