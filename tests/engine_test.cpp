// The one engine (engine/engine.h): render, bake, query and the public API give identical AO for
// the same receivers and keys, because they all run through it; batches keep the caller's order
// across chunks; the Morton order survives NaN; a method is refused where it cannot serve.

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <numeric>
#include <sys/wait.h>

#include <exao/exao.hpp>

#include "bake/bake.h"
#include "bake/document.h"
#include "core/builtin_scenes.h"
#include "core/isa.h"
#include "io/load_scene.h"
#include "engine/engine.h"
#include "engine/morton.h"
#include "lut/mask_engine.h"
#include "tests/test_support.h"

namespace exao {
namespace {

constexpr int kSamples = 64;

engine::Options options_for(engine::Method method = engine::Method::Bvh) {
  engine::Options options;
  options.samples = kSamples;
  options.method = method;
  return options;
}

engine::Engine build(const Scene& scene, const engine::Options& options, engine::Receivers receivers) {
  Result<engine::Engine> built = engine::Engine::build(scene, options, receivers);
  EXPECT_TRUE(built) << built.error().message;
  return std::move(*built);
}

std::vector<api::Receiver> to_api(std::span<const Receiver> receivers) {
  std::vector<api::Receiver> out(receivers.size());
  for (std::size_t i = 0; i < receivers.size(); ++i) {
    const Receiver& r = receivers[i];
    out[i] = {{r.position.x, r.position.y, r.position.z}, {r.normal.x, r.normal.y, r.normal.z}, r.key};
  }
  return out;
}

std::vector<float> api_ao(std::span<const Receiver> receivers) {
  api::Options options;
  options.samples = kSamples;
  // The API's default offset follows each point; the exao program's is 1e-4 of the diagonal
  // (DESIGN.md section 1): that one, from the same box, so that the rays are the same.
  api::Result<api::Engine> first = api::Engine::open("room", options);
  EXPECT_TRUE(first) << first.error().message;
  Bounds box;
  box.extend({first->info().bounds_lo.x, first->info().bounds_lo.y, first->info().bounds_lo.z});
  box.extend({first->info().bounds_hi.x, first->info().bounds_hi.y, first->info().bounds_hi.z});
  options.origin_offset = kDefaultOffsetFraction * box.diagonal();
  api::Result<api::Engine> engine = api::Engine::open("room", options);
  EXPECT_TRUE(engine) << engine.error().message;
  std::vector<float> ao(receivers.size());
  const api::Status status = engine->ao(to_api(receivers), ao);
  EXPECT_TRUE(status.ok()) << status.error().message;
  return ao;
}

// `exao query` on these receivers (written with every digit a float needs, keys included).
std::vector<float> query_ao(std::span<const Receiver> receivers, const test::TempDir& dir) {
  std::string text;
  char line[256];
  for (const Receiver& r : receivers) {
    std::snprintf(line, sizeof line, "%.9g %.9g %.9g %.9g %.9g %.9g %llu\n", r.position.x, r.position.y, r.position.z,
                  r.normal.x, r.normal.y, r.normal.z, static_cast<unsigned long long>(r.key));
    text += line;
  }
  test::write_file(dir / "points.txt", text);
  const std::string command = std::string(EXAO_BINARY) + " query room -n " + std::to_string(kSamples) + " --points " +
                              (dir / "points.txt").string() + " -o " + (dir / "ao.txt").string() + " > /dev/null 2>&1";
  EXPECT_EQ(std::system(command.c_str()), 0) << command;
  std::ifstream in(dir / "ao.txt");
  std::vector<float> out;
  float v = 0.0f;
  while (in >> v) out.push_back(v);
  return out;
}

TEST(Engine, RenderQueryBakeAndTheApiGiveTheSameAo) {
  Result<Scene> room = open_scene("room");
  ASSERT_TRUE(room);
  const engine::Engine pixels = build(*room, options_for(), engine::Receivers::Pixels);
  Result<engine::PixelResult> render = pixels.render(room->cameras.front(), 40, 30);
  ASSERT_TRUE(render) << render.error().message;
  const std::vector<Receiver>& receivers = render->pixels.receivers;
  ASSERT_GT(receivers.size(), 800u);

  // The same receivers and keys as points: the query path, the API and `exao query`.
  const engine::Engine points = build(*room, options_for(), engine::Receivers::Points);
  Result<std::vector<float>> as_points = points.ao(receivers);
  ASSERT_TRUE(as_points);
  const std::vector<float> through_api = api_ao(receivers);
  test::TempDir dir;
  const std::vector<float> through_cli = query_ao(receivers, dir);
  ASSERT_EQ(through_cli.size(), receivers.size());
  std::size_t open = 0;
  for (std::size_t i = 0; i < receivers.size(); ++i) {
    const float rendered = render->masks.ao(i);
    ASSERT_EQ((*as_points)[i], rendered) << "receiver " << i;
    ASSERT_EQ(through_api[i], rendered) << "receiver " << i;
    ASSERT_EQ(through_cli[i], rendered) << "receiver " << i;
    open += rendered == 1.0f;
  }
  EXPECT_LT(open, receivers.size()) << "some pixel is occluded, so the comparison can fail";

  // A bake's receivers (vertices, keys = their index) through the bake, the engine and the API.
  Result<bake::Document> document = bake::Document::open("room");
  ASSERT_TRUE(document) << document.error().message;
  const engine::Engine baking = build(document->scene(), options_for(), engine::Receivers::Points);
  Result<bake::BakeResult> baked = bake::bake(*document, {}, baking);
  ASSERT_TRUE(baked) << baked.error().message;
  ASSERT_GT(baked->receivers.size(), 1000u);
  Result<std::vector<float>> again = points.ao(baked->receivers);
  ASSERT_TRUE(again);
  const std::vector<float> baked_api = api_ao(baked->receivers);
  for (std::size_t i = 0; i < baked->receivers.size(); ++i) {
    ASSERT_EQ((*again)[i], baked->ao[i]) << "vertex receiver " << i;
    ASSERT_EQ(baked_api[i], baked->ao[i]) << "vertex receiver " << i;
  }
}

// The instruction set is named once: the level forced with the isa option (exao --isa) is the
// one the engine's kernels run, and the name EngineInfo::simd reports for it (api/engine.cpp
// reports isa_name of the engine's mask engine; tests/CMakeLists.txt's api_errors_isa_* check
// the API under EXAO_ISA). Every level this CPU runs, and the default.
TEST(Engine, TheIsaOptionIsTheLevelTheKernelsRun) {
  const Scene scene = make_plane_pair();
  for (const Isa isa : supported_isas()) {
    engine::Options options = options_for();
    options.isa = isa;
    for (const engine::Method method : {engine::Method::Bvh, engine::Method::Brute, engine::Method::Raster}) {
      options.method = method;
      const engine::Engine e = build(scene, options, method == engine::Method::Raster ? engine::Receivers::Pixels
                                                                                       : engine::Receivers::Points);
      ASSERT_NE(e.mask_engine(), nullptr);
      EXPECT_STREQ(isa_name(e.mask_engine()->isa()), isa_name(isa)) << engine::method_name(method);
    }
  }
  const engine::Engine by_default = build(scene, options_for(), engine::Receivers::Points);
  EXPECT_EQ(by_default.mask_engine()->isa(), default_isa());
  api::Options options;
  options.samples = kSamples;
  api::Result<api::Engine> through_api = api::Engine::open("plane-pair", options);
  ASSERT_TRUE(through_api) << through_api.error().message;
  EXPECT_STREQ(through_api->info().simd, isa_name(default_isa()));
}

TEST(Engine, BatchesLargerThanAChunkKeepTheCallersOrder) {
  Result<Scene> room = open_scene("room");
  ASSERT_TRUE(room);
  engine::Options options = options_for();
  options.samples = 32;
  const engine::Engine pixels = build(*room, options, engine::Receivers::Pixels);
  Result<PixelReceivers> grid = pixels.pixel_receivers(room->cameras.front(), 320, 240);
  ASSERT_TRUE(grid);
  std::vector<Receiver> receivers = grid->receivers;
  ASSERT_GT(receivers.size(), engine::kChunk + 1000);
  std::reverse(receivers.begin(), receivers.end());  // far from Morton order
  const engine::Engine points = build(*room, options, engine::Receivers::Points);
  std::vector<float> ao(receivers.size());
  std::vector<std::uint32_t> blocked(receivers.size());
  std::vector<std::uint64_t> masks(receivers.size() * points.mask_words());
  std::size_t last_done = 0;
  engine::RunOptions run;
  run.progress = [&](std::size_t done, std::size_t total) {
    EXPECT_EQ(total, receivers.size());
    last_done = std::max(last_done, done);
  };
  ASSERT_TRUE(points.run(receivers, {ao, blocked, masks}, run));
  EXPECT_EQ(last_done, receivers.size());
  std::array<std::uint64_t, 1> one{};
  for (std::size_t i = 0; i < receivers.size(); i += 997) {
    points.mask_one(receivers[i], one);
    EXPECT_EQ(one[0], masks[i]) << "receiver " << i;
    EXPECT_EQ(static_cast<int>(blocked[i]), std::popcount(one[0])) << "receiver " << i;
    EXPECT_EQ(ao[i], ao_from_blocked(std::popcount(one[0]), 32)) << "receiver " << i;
  }
  std::vector<float> wrong(3);
  EXPECT_FALSE(points.run(receivers, {wrong, {}, {}}));
}

// Shards (exao --shard): whole chunks of the Morton order that partition the batch, each
// receiver's answer the whole batch's, and counts supplied back give the same outputs.
TEST(Engine, ShardsPartitionTheBatchInWholeChunksWithTheWholeBatchsAnswers) {
  Result<Scene> room = open_scene("room");
  ASSERT_TRUE(room);
  engine::Options options = options_for();
  options.samples = 32;
  const engine::Engine pixels = build(*room, options, engine::Receivers::Pixels);
  Result<PixelReceivers> grid = pixels.pixel_receivers(room->cameras.front(), 400, 400);
  ASSERT_TRUE(grid);
  const std::vector<Receiver>& receivers = grid->receivers;
  ASSERT_GT(receivers.size(), 2 * engine::kChunk);
  const engine::Engine points = build(*room, options, engine::Receivers::Points);
  std::vector<std::uint32_t> whole(receivers.size());
  ASSERT_TRUE(points.run(receivers, {{}, whole, {}}));

  for (const std::size_t count : {std::size_t{1}, std::size_t{2}, std::size_t{3}, std::size_t{7}}) {
    constexpr std::uint32_t kUnset = ~std::uint32_t{0};
    std::vector<std::uint32_t> seen(receivers.size(), kUnset);
    for (std::size_t k = 0; k < count; ++k) {
      const engine::Shard shard{k, count};
      const std::vector<std::uint32_t> mine = engine::shard_receivers(receivers, shard);
      const auto [first, last] = engine::shard_chunks(receivers.size(), shard);
      EXPECT_EQ(mine.size(), std::min(last * engine::kChunk, receivers.size()) - std::min(first * engine::kChunk, receivers.size()));
      std::vector<std::uint32_t> part(receivers.size(), kUnset);
      engine::RunOptions run;
      run.shard = shard;
      std::size_t last_done = 0;
      run.progress = [&](std::size_t done, std::size_t total) {
        EXPECT_EQ(total, mine.size());
        last_done = std::max(last_done, done);
      };
      ASSERT_TRUE(points.run(receivers, {{}, part, {}}, run));
      EXPECT_EQ(last_done, mine.size());
      std::size_t written = 0;
      for (const std::uint32_t r : mine) {
        EXPECT_EQ(seen[r], kUnset) << "receiver " << r << " in two shards of " << count;
        seen[r] = part[r];
        EXPECT_EQ(part[r], whole[r]) << "receiver " << r << ", shard " << k << " of " << count;
      }
      for (const std::uint32_t b : part) written += b != kUnset;
      EXPECT_EQ(written, mine.size()) << "shard " << k << " of " << count << " wrote outside its receivers";
    }
    EXPECT_EQ(seen, whole) << count << " shards";
  }

  // Counts supplied back (exao merge): the same AO as the whole run, and nothing cast.
  std::vector<float> ao(receivers.size()), again(receivers.size());
  ASSERT_TRUE(points.run(receivers, {ao, {}, {}}));
  engine::RunOptions supplied;
  supplied.supplied_blocked = whole;
  ASSERT_TRUE(points.run(receivers, {again, {}, {}}, supplied));
  EXPECT_EQ(ao, again);
  std::vector<std::uint64_t> masks(receivers.size() * points.mask_words());
  EXPECT_FALSE(points.run(receivers, {{}, {}, masks}, supplied));
  engine::RunOptions bad;
  bad.shard = engine::Shard{3, 3};
  EXPECT_FALSE(points.run(receivers, {ao, {}, {}}, bad));
}

// A texture bake's shards split the texels of one chart (a seam inside the map), and the map is
// made once from every shard's answers: here each shard's receivers answer 8 * K blocked rays, so
// a texel's value says which shards its samples came from.
TEST(Engine, TextureShardsMeetInsideChartsAndTheMapIsMadeFromAllOfThem) {
  bake::ConvertOptions convert;
  convert.atlas_size = 512;
  convert.atlas_padding = 10;
  Result<bake::Document> document = bake::Document::open("room", convert);
  ASSERT_TRUE(document) << document.error().message;
  bake::BakeOptions options;
  options.target = bake::Target::Texture;
  options.texture_size = 512;
  Result<std::vector<Receiver>> receivers = bake::bake_receivers(*document, options);
  ASSERT_TRUE(receivers) << receivers.error().message;
  ASSERT_GT(receivers->size(), 4 * engine::kChunk);
  std::vector<std::uint32_t> blocked(receivers->size(), ~std::uint32_t{0});
  for (std::size_t k = 0; k < 4; ++k) {
    for (const std::uint32_t r : engine::shard_receivers(*receivers, {k, 4})) blocked[r] = static_cast<std::uint32_t>(8 * k);
  }
  for (const std::uint32_t b : blocked) ASSERT_NE(b, ~std::uint32_t{0});  // the shards cover every receiver
  engine::Options engine_options = options_for();
  engine_options.samples = 32;
  const engine::Engine engine = build(document->scene(), engine_options, engine::Receivers::Points);
  engine::RunOptions run;
  run.supplied_blocked = blocked;
  Result<bake::BakeResult> result = bake::bake(*document, options, engine, run);
  ASSERT_TRUE(result) << result.error().message;
  ASSERT_EQ(result->maps.size(), 1u);
  const bake::AoMap& map = result->maps.front();
  const auto pure = [](float ao) {
    for (int k = 0; k < 4; ++k) {
      if (ao == ao_from_blocked(8 * k, 32)) return true;
    }
    return false;
  };
  std::size_t seams = 0, mixed = 0, margin_from_two = 0;
  for (int y = 0; y + 1 < map.size; ++y) {
    for (int x = 0; x + 1 < map.size; ++x) {
      const std::size_t at = static_cast<std::size_t>(y) * map.size + x;
      if (map.filled[at] == 1 && !pure(map.ao[at])) ++mixed;  // samples of two shards in one texel
      for (const std::size_t next : {at + 1, at + map.size}) {
        if (map.filled[at] == 1 && map.filled[next] == 1 && map.ao[at] != map.ao[next]) ++seams;
        if (map.filled[at] == 2 && map.filled[next] == 2 && map.ao[at] != map.ao[next]) ++margin_from_two;
      }
    }
  }
  EXPECT_GT(seams, 0u) << "no two neighbouring covered texels come from different shards";
  EXPECT_GT(mixed, 0u) << "no texel holds samples of two shards";
  EXPECT_GT(margin_from_two, 0u) << "the dilated margin does not follow the shards' values";
}

TEST(Engine, MortonOrderIsAPermutationEvenWithNaN) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  std::vector<Receiver> receivers;
  for (int i = 0; i < 100; ++i) receivers.push_back({{float(i % 7), float(i % 5), float(i)}, {0, 0, 1}, 0});
  receivers[3].position.x = nan;
  receivers[40].position = {nan, nan, nan};
  receivers[77].position.y = inf;
  std::vector<std::uint32_t> order = engine::morton_order(receivers);
  std::sort(order.begin(), order.end());
  std::vector<std::uint32_t> identity(receivers.size());
  std::iota(identity.begin(), identity.end(), 0u);
  EXPECT_EQ(order, identity);
  // Neighbours come together: the first two in Morton order are closer than the average pair.
  const std::vector<std::uint32_t> sorted = engine::morton_order(std::span<const Receiver>(receivers).subspan(41, 30));
  EXPECT_LT(glm::length(receivers[41 + sorted[0]].position - receivers[41 + sorted[1]].position), 15.0f);
}

TEST(Engine, EachMethodServesWhatItDeclares) {
  Result<Scene> room = open_scene("room");
  ASSERT_TRUE(room);
  for (const engine::Method method : {engine::Method::Embree, engine::Method::Brute, engine::Method::Bvh, engine::Method::Raster}) {
    const engine::Capabilities& c = engine::capabilities(method);
    EXPECT_TRUE(c.pixels) << engine::method_name(method);
    Result<engine::Engine> as_points = engine::Engine::build(*room, options_for(method), engine::Receivers::Points);
    EXPECT_EQ(as_points.has_value(), c.points) << engine::method_name(method);
  }
  Result<engine::Engine> raster = engine::Engine::build(*room, options_for(engine::Method::Raster), engine::Receivers::Points);
  ASSERT_FALSE(raster);
  EXPECT_EQ(raster.error().message.rfind("method: raster", 0), 0u) << raster.error().message;
  // Built for pixels, raster still refuses points when asked for them.
  const engine::Engine pixels = build(*room, options_for(engine::Method::Raster), engine::Receivers::Pixels);
  const Receiver one{{0.0f, 0.01f, 0.0f}, {0.0f, 1.0f, 0.0f}, 0};
  Result<std::vector<float>> ao = pixels.ao(std::span<const Receiver>(&one, 1));
  ASSERT_FALSE(ao);
  EXPECT_EQ(ao.error().message.rfind("method: raster", 0), 0u) << ao.error().message;
  // And the public API says the same, naming its own field.
  api::Options options;
  options.backend = api::Backend::Raster;
  api::Result<api::Engine> refused = api::Engine::open("room", options);
  ASSERT_FALSE(refused);
  EXPECT_EQ(refused.code(), api::StatusCode::InvalidArgument);
  EXPECT_EQ(refused.error().message.rfind("options.backend: raster", 0), 0u) << refused.error().message;
}

TEST(Engine, OptionErrorsNameTheOptionAndTheValue) {
  engine::Options options = options_for();
  options.samples = 100;
  Result<void> checked = engine::check_options(options);
  ASSERT_FALSE(checked);
  EXPECT_EQ(checked.error().message, "samples: must be a multiple of 32 from 32 to 1024, got 100");
  EXPECT_EQ(engine::option_of(checked.error().message), "samples");
  options = options_for();
  options.bvh.branching = 3;
  checked = engine::check_options(options);
  ASSERT_FALSE(checked);
  EXPECT_EQ(checked.error().message, "bvh.branching: must be 2 or 4, got 3");
  options = options_for();
  options.radius = {-1.0f, false};
  Result<Scene> room = open_scene("room");
  ASSERT_TRUE(room);
  Result<engine::Engine> built = engine::Engine::build(*room, options, engine::Receivers::Points);
  ASSERT_FALSE(built);
  EXPECT_EQ(built.error().message.rfind("radius: must be a finite length > 0, got -1", 0), 0u) << built.error().message;
  EXPECT_EQ(engine::option_of("room: no such file"), std::nullopt);
}

TEST(Engine, TheDefaultRadiusIsFivePercentOfTheDiagonal) {
  Result<Scene> room = open_scene("room");
  ASSERT_TRUE(room);
  const engine::Engine points = build(*room, options_for(), engine::Receivers::Points);
  EXPECT_EQ(points.radius(), engine::kDefaultRadius.resolve(room->bounds().diagonal()));
  EXPECT_FLOAT_EQ(points.radius(), 0.05f * room->bounds().diagonal());
  api::Result<api::Engine> api_engine = api::Engine::open("room");
  ASSERT_TRUE(api_engine);
  EXPECT_EQ(api_engine->info().radius, points.radius());
}

}  // namespace
}  // namespace exao
