// core/enum_names.h: every enum's table of names. Each value's name parses back to the value,
// names are unique within their enum, every value of the enum is in its table (the tables are
// the only place the names are written), and a name that is not in the table is refused, by
// parse_enum and by each parse function with its message.

#include <gtest/gtest.h>

#include <set>
#include <string>

#include "bvh/hybrid.h"
#include "core/cutouts.h"
#include "core/embree_reference.h"
#include "core/enum_names.h"
#include "core/isa.h"
#include "core/sample_pattern.h"
#include "engine/capabilities.h"
#include "engine/options.h"
#include "lut/mask_engine.h"
#include "lut/plane_table.h"
#include "raster/lod.h"
#include "ssao/compare.h"

namespace exao {
namespace {

// `count`: how many values the enum has (its last enumerator + 1), so that a value missing from
// the table is seen.
template <class E>
void expect_table_round_trips(std::size_t count) {
  constexpr auto names = all_names<E>();
  constexpr auto values = all_values<E>();
  EXPECT_EQ(values.size(), count);
  std::set<std::string_view> unique_names(names.begin(), names.end());
  EXPECT_EQ(unique_names.size(), names.size()) << "a name stands twice";
  std::set<E> unique_values(values.begin(), values.end());
  EXPECT_EQ(unique_values.size(), values.size()) << "a value stands twice";
  for (std::size_t v = 0; v < count; ++v) {
    const E value = static_cast<E>(v);
    const std::string name = name_of(value);
    SCOPED_TRACE(name);
    EXPECT_NE(name, "?") << "value " << v << " has no name";
    const std::optional<E> parsed = parse_enum<E>(name);
    ASSERT_TRUE(parsed.has_value());
    EXPECT_EQ(*parsed, value);
    EXPECT_EQ(std::string(name_of(*parsed)), name);
  }
  EXPECT_STREQ(name_of(static_cast<E>(count)), "?");
  EXPECT_FALSE(parse_enum<E>("no-such-name").has_value());
  EXPECT_FALSE(parse_enum<E>("").has_value());
  // Exact names only: no case folding, no surrounding space.
  EXPECT_FALSE(parse_enum<E>(" " + std::string(names[0])).has_value());
}

TEST(EnumNames, EveryTableRoundTripsWithUniqueNames) {
  expect_table_round_trips<engine::Method>(5);
  expect_table_round_trips<engine::Receivers>(2);
  expect_table_round_trips<ssao::Method>(15);
  expect_table_round_trips<Isa>(5);
  expect_table_round_trips<Falloff>(3);
  expect_table_round_trips<BlendRule>(3);
  expect_table_round_trips<EmbreeRays>(4);
  expect_table_round_trips<bvh::HybridPolicy>(3);
  expect_table_round_trips<raster::LodFilter>(2);
  expect_table_round_trips<lut::TableKind>(2);
  expect_table_round_trips<lut::MaskMode>(2);
}

TEST(EnumNames, TheNamedFunctionsAreTheTables) {
  EXPECT_STREQ(engine::method_name(engine::Method::Auto), "auto");
  EXPECT_STREQ(engine::receivers_name(engine::Receivers::Pixels), "pixels");
  EXPECT_STREQ(ssao::compare_method_name(ssao::Method::HbaoPlus), "hbao+");
  EXPECT_STREQ(isa_name(Isa::Avx512), "avx512");
  EXPECT_STREQ(falloff_name(Falloff::Quadratic), "quadratic");
  EXPECT_STREQ(blend_rule_name(BlendRule::Stochastic), "stochastic");
  EXPECT_STREQ(embree_rays_name(EmbreeRays::Packet16), "packet16");
  EXPECT_STREQ(bvh::hybrid_policy_name(bvh::HybridPolicy::Masks), "masks");
  EXPECT_STREQ(raster::lod_filter_name(raster::LodFilter::BoundedDistance), "distance");
  EXPECT_STREQ(lut::table_kind_name(lut::TableKind::Directions), "directions");
  EXPECT_STREQ(lut::mask_mode_name(lut::MaskMode::Lut), "lut");
  EXPECT_EQ(name_list<lut::MaskMode>(), "lut or exact");
  EXPECT_EQ(name_list<EmbreeRays>(", "), "single, packet4, packet8, packet16");
  static_assert(parse_enum<Isa>("sse4") == Isa::Sse4, "the tables are constexpr");
}

// The messages list the names in the tables' order, as they did when each was written by hand.
TEST(EnumNames, UnknownNamesAreRefusedWithTheOptionAndTheList) {
  EXPECT_EQ(engine::parse_method("fast").error().message,
            "method: unknown method 'fast' (auto, embree, brute, bvh or raster), got 'fast'");
  EXPECT_EQ(parse_isa("avx9").error().message,
            "isa: 'avx9' is not an instruction set (auto, scalar, sse2, sse4, avx2 or avx512)");
  EXPECT_EQ(parse_falloff("cubic").error().message, "falloff: unknown falloff 'cubic' (constant, linear or quadratic)");
  EXPECT_EQ(parse_blend_rule("x").error().message, "blend: unknown rule 'x' (opaque, cutoff or stochastic)");
  EXPECT_EQ(parse_embree_rays("packet2").error().message,
            "embree.rays: unknown mode 'packet2' (single, packet4, packet8 or packet16)");
  EXPECT_EQ(bvh::parse_hybrid_policy("both").error().message, "hybrid: unknown policy 'both' (adaptive, masks or rays)");
  EXPECT_EQ(raster::parse_lod_filter("box").error().message, "lod_filter: unknown filter 'box' (envelope or distance)");
  EXPECT_EQ(lut::parse_mask_mode("table").error().message, "masks: unknown mask mode 'table' (lut or exact)");
  EXPECT_EQ(ssao::parse_methods("ssao").error().message,
            "methods: unknown method 'ssao' (all, hbao, hbao+, vao, sdao, svao, rtsvao, abuffer, shbao+, shbao+2d, "
            "sdao+, mvsdao+, rtsvao-rays, abuffer-m4, abuffer-m8, abuffer-oit)");
}

}  // namespace
}  // namespace exao
