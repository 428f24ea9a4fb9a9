// The screen-space methods of ssao/ on scenes with a known answer or known bounds, the hidden
// occluder of seed 000's Fig. 1-2 (single-layer methods miss it, multi-layer ones see part of
// it, exact AO sees all of it), the stochastic depth map's statistics, A-buffer opacity, and the
// stereo metric of seed 003 with exact AO's world-space keys.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numbers>
#include <numeric>
#include <set>

#include "bvh/bvh.h"
#include "bvh/occlusion.h"
#include "core/builtin_scenes.h"
#include "core/embree_reference.h"
#include "io/load_scene.h"
#include "core/world_key.h"
#include "lut/mask_engine.h"
#include "ssao/abuffer_ao.h"
#include "ssao/abuffer_oit.h"
#include "ssao/grazing_box.h"
#include "ssao/list_compression.h"
#include "ssao/sd_hbao_plus.h"
#include "ssao/stereo_filter.h"
#include "ssao/stereo_hbao_plus.h"
#include "ssao/compare.h"
#include "ssao/fragment_buffer.h"
#include "ssao/hbao.h"
#include "ssao/hbao_plus.h"
#include "ssao/sd_hbao.h"
#include "ssao/stereo.h"
#include "ssao/stochastic_depth.h"
#include "ssao/svao.h"
#include "ssao/vao.h"
#include "tests/test_support.h"

namespace exao::ssao {
namespace {

// Exact AO by the bvh backend, as `exao compare` computes it.
struct Exact {
  Scene scene;
  ShadowRays rays;
  lut::TriangleSet triangles;
  std::optional<bvh::Bvh> tree;
  std::optional<lut::MaskEngine> engine;
  // RT-SVAO's column rays, as `exao compare` casts them: Embree's nearest hits.
  std::shared_ptr<EmbreeScene> embree;
  SegmentHits hits;

  Exact(Scene s, float radius, int samples) : scene(std::move(s)), triangles(lut::TriangleSet::build(scene)) {
    rays = *make_shadow_rays(*make_sample_pattern(samples, Falloff::Constant), radius, 1e-4f * scene.bounds().diagonal());
    tree.emplace(std::move(*bvh::Bvh::build(triangles)));
    engine.emplace(std::move(*lut::MaskEngine::build(rays, lut::MaskMode::Exact)));
    embree = std::make_shared<EmbreeScene>(std::move(*EmbreeScene::build(scene)));
    hits = segment_hits_by_closest([e = embree](const glm::dvec3& origin, const glm::dvec3& direction) -> std::optional<double> {
      const auto hit = e->closest_hit(glm::vec3(origin), glm::vec3(direction));
      if (!hit) return std::nullopt;
      return static_cast<double>(hit->distance);
    });
  }
  [[nodiscard]] std::vector<float> operator()(std::span<const Receiver> receivers) const {
    const MaskSet masks = bvh::occlusion(*tree, *engine, receivers);
    std::vector<float> ao(receivers.size());
    for (std::size_t i = 0; i < ao.size(); ++i) ao[i] = masks.ao(i);
    return ao;
  }
};

CompareOptions options_for(float radius) {
  CompareOptions o;
  o.settings.radius = radius;
  o.settings.blur_radius = 0;  // per-pixel values, so the tests see each estimator itself
  return o;
}

const MethodResult& result(const ViewResult& r, Method m) {
  for (const MethodResult& x : r.methods) {
    if (x.method == m) return x;
  }
  throw std::logic_error("method not run");
}

// Mean of a per-pixel image over the chosen pixels.
double mean_over(const std::vector<float>& ao, const std::vector<std::uint32_t>& pixels) {
  double sum = 0.0;
  for (const std::uint32_t p : pixels) sum += ao[p];
  return sum / static_cast<double>(pixels.size());
}

Scene floor_only() {
  Scene s = make_hidden_box(false, false);
  s.name = "floor";
  return s;
}

TEST(Ssao, OpenFloorIsOpenForEveryMethod) {
  const Exact exact(floor_only(), 1.0f, 128);
  const ViewResult r = compare_view(exact.scene, exact.scene.cameras[0], 96, 72, options_for(1.0f), std::cref(exact), exact.hits);
  std::size_t seen = 0;
  for (std::size_t p = 0; p < r.view.pixel_count(); ++p) {
    if (!r.view.valid[p]) continue;
    ++seen;
    EXPECT_FLOAT_EQ(r.exact[p], 1.0f);
    // A plane below the bias holds no horizon and no HBAO+ sample above it.
    for (const Method m : {Method::Hbao, Method::HbaoPlus, Method::SdHbao, Method::Abuffer, Method::StereoHbaoPlus, Method::StereoHbaoPlus2d,
                           Method::SdHbaoPlus, Method::MvSdHbaoPlus, Method::AbufferM4, Method::AbufferM8, Method::AbufferOit}) {
      EXPECT_EQ(result(r, m).ao[p], 1.0f) << compare_method_name(m);
    }
    for (const MethodResult& m : r.methods) {
      EXPECT_GE(m.ao[p], 0.0f);
      EXPECT_LE(m.ao[p], 1.0f);
    }
  }
  ASSERT_GT(seen, 1000u);
  // VAO's eight line samples estimate the half ball's volume: unbiased, not exact, on a tilted
  // plane (VaoIsUnbiasedOnOpenPlanes measures how close).
  for (const Method m : {Method::Vao, Method::SdSvao, Method::RtSvaoRays}) {
    std::vector<std::uint32_t> all;
    for (std::size_t p = 0; p < r.view.pixel_count(); ++p) {
      if (r.view.valid[p]) all.push_back(static_cast<std::uint32_t>(p));
    }
    EXPECT_NEAR(mean_over(result(r, m).ao, all), 1.0, 0.02) << compare_method_name(m);
  }
}

// The mean of VAO's per-pixel values over some pixels, and how far from it the pattern's noise
// may take it: the values' standard deviation s over the square root of the number of 4 x 4
// blocks (a block's 16 pixels take the 16 rotations of the pattern, so a block, not a pixel, is
// the independent unit; within a block the rotations are stratified, so this is conservative),
// times 4.
struct PatternMean {
  double mean = 0.0, tolerance = 0.0;
  std::size_t pixels = 0;
};

PatternMean pattern_mean(const std::vector<float>& ao, const std::vector<std::uint32_t>& pixels) {
  PatternMean m;
  m.pixels = pixels.size();
  m.mean = mean_over(ao, pixels);
  double sq = 0.0;
  for (const std::uint32_t p : pixels) sq += (ao[p] - m.mean) * (ao[p] - m.mean);
  const double n = static_cast<double>(pixels.size());
  const double s = std::sqrt(sq / (n - 1.0));
  m.tolerance = 4.0 * s / std::sqrt(n / 16.0);
  return m;
}

// Seed 001's estimator on an open plane: exact AO is 1, and VAO must average 1 within the
// pattern's noise at every tilt and radius: with xi over a full turn (each sample's angle
// uniform), with no sample read from its own pixel, and with the ball below a pixel open.
TEST(Ssao, VaoIsUnbiasedOnOpenPlanes) {
  const Scene floor = floor_only();
  VaoOptions o;
  for (const float elevation : {20.0f, 45.0f, 70.0f}) {
    const float e = glm::radians(elevation);
    const Camera camera = look_at({0.0f, 4.0f * std::sin(e), 4.0f * std::cos(e)}, {0.0f, 0.0f, 0.0f}, 50.0f);
    const View view = make_view(floor, camera, 240, 180);
    std::vector<std::uint32_t> seen;
    for (std::size_t p = 0; p < view.pixel_count(); ++p) {
      if (view.valid[p]) seen.push_back(static_cast<std::uint32_t>(p));
    }
    ASSERT_GT(seen.size(), 10000u);
    for (const double radius : {1.0, 0.4, 0.1, 0.05}) {
      Settings settings;
      settings.radius = radius;
      const VaoResult r = vao(view, settings, o);
      const PatternMean m = pattern_mean(r.ao, seen);
      std::printf("VAO open floor, elevation %2.0f deg, r = %.2f: mean %.4f (bias %+.4f, tolerance %.4f)\n", static_cast<double>(elevation), radius,
                  m.mean, m.mean - 1.0, m.tolerance);
      EXPECT_LT(m.tolerance, 0.02);
      EXPECT_NEAR(m.mean, 1.0, m.tolerance) << "elevation " << elevation << ", r = " << radius;
      for (const std::uint8_t f : r.flags) ASSERT_EQ(f, 0);  // nothing in front of an open plane
    }
  }
}

// The room's ceiling is open where exact AO is 1: VAO must average 1 there too (it averaged
// 0.95 with xi limited to one sample's sector).
TEST(Ssao, VaoIsUnbiasedOnTheRoomsCeiling) {
  const Exact exact(make_room(), 0.67f, 128);
  CompareOptions options = options_for(0.67f);
  options.methods = {Method::Vao};
  const ViewResult r = compare_view(exact.scene, exact.scene.cameras[0], 320, 240, options, std::cref(exact), exact.hits);
  // Ceiling points more than r from the walls (x = +-5, z = +-4) and from the column that
  // reaches the ceiling (x in [3.2, 3.8], z in [-3.6, -3.0]): nothing within r but the ceiling.
  const float radius = 0.67f;
  std::vector<std::uint32_t> ceiling;
  for (std::size_t p = 0; p < r.view.pixel_count(); ++p) {
    const glm::vec3 x = r.view.position[p];
    const float dx = std::max({3.2f - x.x, x.x - 3.8f, 0.0f}), dz = std::max({-3.6f - x.z, x.z + 3.0f, 0.0f});
    const bool clear = std::abs(x.x) < 5.0f - radius && std::abs(x.z) < 4.0f - radius && dx * dx + dz * dz > radius * radius;
    if (!(r.view.valid[p] && r.view.normal[p].y < -0.99f && clear)) continue;
    ASSERT_EQ(r.exact[p], 1.0f);
    // And only ceiling on screen within the projected radius: the halo model rightly counts a
    // surface up to 2 + tau radii in front of the ball (the column, seen beside the ceiling).
    const auto reach = static_cast<int>(std::ceil(radius * r.view.pixels_per_unit(r.view.depth[p])));
    const int px = static_cast<int>(p % 320), py = static_cast<int>(p / 320);
    bool only_ceiling = true;
    for (int y = std::max(py - reach, 0); y <= std::min(py + reach, 239) && only_ceiling; ++y) {
      for (int qx = std::max(px - reach, 0); qx <= std::min(px + reach, 319); ++qx) {
        const std::size_t q = static_cast<std::size_t>(y) * 320 + static_cast<std::size_t>(qx);
        if (!r.view.valid[q] || r.view.normal[q].y > -0.99f) only_ceiling = false;
      }
    }
    if (only_ceiling) ceiling.push_back(static_cast<std::uint32_t>(p));
  }
  ASSERT_GT(ceiling.size(), 200u);
  const PatternMean m = pattern_mean(result(r, Method::Vao).ao, ceiling);
  std::printf("VAO on the room's open ceiling (%zu pixels): mean %.4f, tolerance %.4f\n", m.pixels, m.mean, m.tolerance);
  EXPECT_NEAR(m.mean, 1.0, m.tolerance);
}

// Seed 000's Alg. 2 on a case computed here in closed form: the receiver P at the centre of the
// image on a plane tilted 30 degrees about the camera's x axis, and every other pixel holding a
// plane parallel to the image, 1 unit nearer the eye (an occluder within r wherever the walk
// looks; pixels only hold the G-buffer, so it need not be a consistent scene). One step per
// direction: its sample is where the ray through the step's screen point meets the occluder
// plane, at angle phi from the XY plane, and the direction gains sin phi - sin(t + bias), t the
// tangent's angle along it. The tangent-plane form measures sin phi from the normal instead.
TEST(Ssao, HbaoFollowsAlgorithm2sGain) {
  View view;
  view.width = view.height = 33;
  view.eye = {0.0, 0.0, 0.0};
  view.forward = {0.0, 0.0, -1.0};
  view.up = {0.0, 1.0, 0.0};
  view.right = {1.0, 0.0, 0.0};
  view.tan_half = std::tan(glm::radians(30.0));
  view.aspect = 1.0;
  const std::size_t n_pixels = 33 * 33, p = 16 * 33 + 16;
  const double depth = 10.0, in_front = 1.0, tilt = glm::radians(30.0);
  const glm::dvec3 P(0.0, 0.0, -depth), n(0.0, std::sin(tilt), std::cos(tilt));
  view.valid.assign(n_pixels, 1);
  view.position.resize(n_pixels);
  view.normal.assign(n_pixels, glm::vec3(0.0f, 0.0f, 1.0f));
  view.depth.assign(n_pixels, static_cast<float>(depth - in_front));
  for (std::size_t q = 0; q < n_pixels; ++q) view.position[q] = glm::vec3(view.point_at(q, depth - in_front));
  view.position[p] = glm::vec3(P);
  view.normal[p] = glm::vec3(n);
  view.depth[p] = static_cast<float>(depth);
  ASSERT_EQ(view.centre(p), glm::dvec2(16.5, 16.5));  // its centre ray is the view axis

  Settings settings;
  settings.radius = 4.0;
  HbaoOptions o;
  o.steps = 1;
  const double radius_px = settings.radius * view.pixels_per_unit(depth);
  const double first_step = 1.0 + block_jitter(p, view.width, 1) * radius_px / 2.0, rotation = block_jitter(p, view.width, 0);
  double alg2 = 0.0, tangent_form = 0.0;
  int rising = 0;
  for (int d = 0; d < o.directions; ++d) {
    const double angle = 2.0 * std::numbers::pi * (d + rotation) / o.directions;
    const glm::dvec2 dir(std::cos(angle), std::sin(angle));
    // The sample: the ray through the step's screen point, at the occluder's depth.
    const double sx = (2.0 * (16.5 + first_step * dir.x) / 33.0 - 1.0) * view.tan_half;
    const double sy = (1.0 - 2.0 * (16.5 + first_step * dir.y) / 33.0) * view.tan_half;
    const glm::dvec3 v = (depth - in_front) * glm::dvec3(sx, sy, -1.0) - P;
    ASSERT_LT(glm::length(v), settings.radius);
    const double sin_phi = v.z / glm::length(v);
    // The tangent along the screen direction (x right, y up in view space): (D, z) with n . (D, z) = 0.
    const glm::dvec2 D(dir.x, -dir.y);
    const double z = -(n.y * D.y) / n.z;
    const double t = std::atan(z);
    alg2 += std::max(0.0, sin_phi - std::sin(t + o.bias));
    rising += sin_phi > std::sin(t + o.bias);
    tangent_form += std::max(0.0, glm::dot(v, n) / glm::length(v) - std::sin(o.bias));
  }
  ASSERT_GT(rising, 0);
  const double expected = 1.0 - alg2 / o.directions, expected_tangent = 1.0 - tangent_form / o.directions;
  std::printf("Alg. 2: %.4f, tangent-plane form: %.4f\n", expected, expected_tangent);
  ASSERT_GT(std::abs(expected - expected_tangent), 0.05);  // the case tells the two forms apart
  EXPECT_NEAR(hbao(view, settings, o)[p], expected, 1e-5);
  o.angles = Angles::Tangent;
  EXPECT_NEAR(hbao(view, settings, o)[p], expected_tangent, 1e-5);
  // sin^2 is the cosine-weighted share only above the tangent plane.
  o.cosine = true;
  EXPECT_TRUE(check(o));
  o.angles = Angles::ViewPlane;
  EXPECT_FALSE(check(o));
}

// Every method is timed with its own passes: the three whose maps come from the A-buffer are
// charged its rasterisation (seed 000 Table 2, seed 001 Table 1 count the map's geometry pass).
TEST(Ssao, TimesIncludeTheMapsGeometryPass) {
  const Exact exact(make_room(), 0.67f, 32);
  CompareOptions options = options_for(0.67f);
  const ViewResult r = compare_view(exact.scene, exact.scene.cameras[0], 64, 48, options, std::cref(exact), exact.hits);
  ASSERT_GT(r.fragment_seconds, 0.0);
  for (const MethodResult& m : r.methods) {
    const bool map = m.method == Method::SdHbao || m.method == Method::SdSvao || m.method == Method::Abuffer || m.method == Method::SdHbaoPlus ||
                     list_nodes(m.method) > 0 || m.method == Method::AbufferOit;
    if (m.method == Method::MvSdHbaoPlus) {
      EXPECT_GT(m.map_seconds, r.fragment_seconds);  // and the secondary view's A-buffer
    } else {
      EXPECT_EQ(m.map_seconds, map ? r.fragment_seconds : 0.0) << compare_method_name(m.method);
    }
    EXPECT_GE(m.seconds, m.map_seconds) << compare_method_name(m.method);
  }
}

// HBAO's rotation (stream 0) and step offset (stream 1) over a 4 x 4 block: each takes all 16
// strata, and the offset's stratum is not a fixed shift of the rotation's (which would tie the
// first step's distance to the direction).
TEST(Ssao, RotationAndStepOffsetAreStratifiedApart) {
  std::set<int> rotations, offsets, differences;
  for (std::size_t y = 0; y < 4; ++y) {
    for (std::size_t x = 0; x < 4; ++x) {
      const int a = static_cast<int>(16.0 * block_jitter(y * 8 + x, 8, 0));
      const int b = static_cast<int>(16.0 * block_jitter(y * 8 + x, 8, 1));
      rotations.insert(a);
      offsets.insert(b);
      differences.insert(((b - a) % 16 + 16) % 16);
    }
  }
  EXPECT_EQ(rotations.size(), 16u);
  EXPECT_EQ(offsets.size(), 16u);
  EXPECT_GT(differences.size(), 4u);
}

// A floor point at the foot of a wall that reaches beyond r: the wall blocks half the hemisphere
// (AO = 1/2 with cosine weighting, and half the ball's volume for VAO); a point farther than r
// from it is open.
TEST(Ssao, FootOfAWallIsHalfOccludedAndFarFloorIsOpen) {
  Scene scene = make_hidden_box(false, false);
  // A 12 x 4 wall in the plane z = -1, facing +Z, as two triangles.
  scene.add_triangle({-6.0f, 0.0f, -1.0f}, {6.0f, 0.0f, -1.0f}, {6.0f, 4.0f, -1.0f}, false, 0);
  scene.add_triangle({-6.0f, 0.0f, -1.0f}, {6.0f, 4.0f, -1.0f}, {-6.0f, 4.0f, -1.0f}, false, 0);
  const float radius = 1.0f;
  const Exact exact(std::move(scene), radius, 256);
  const ViewResult r = compare_view(exact.scene, exact.scene.cameras[0], 160, 120, options_for(radius), std::cref(exact), exact.hits);
  std::vector<std::uint32_t> foot, far;
  for (std::size_t p = 0; p < r.view.pixel_count(); ++p) {
    if (!r.view.valid[p] || std::abs(r.view.normal[p].y) < 0.99f) continue;  // floor pixels
    const glm::vec3 x = r.view.position[p];
    if (std::abs(x.x) > 2.0f) continue;
    if (x.z > -0.98f && x.z < -0.93f) foot.push_back(static_cast<std::uint32_t>(p));
    if (x.z > 0.2f && x.z < 1.0f) far.push_back(static_cast<std::uint32_t>(p));
  }
  ASSERT_GT(foot.size(), 10u);
  ASSERT_GT(far.size(), 200u);
  EXPECT_NEAR(mean_over(r.exact, foot), 0.5, 0.04);
  for (const MethodResult& m : r.methods) {
    // Sees the wall, but no method can block more than the wall's half of the hemisphere by much.
    EXPECT_LT(mean_over(m.ao, foot), 0.8) << compare_method_name(m.method);
    EXPECT_GT(mean_over(m.ao, foot), 0.3) << compare_method_name(m.method);
    if (m.method != Method::Vao && m.method != Method::SdSvao && m.method != Method::RtSvao && m.method != Method::RtSvaoRays) {
      for (const std::uint32_t p : far) ASSERT_EQ(m.ao[p], 1.0f) << compare_method_name(m.method) << " pixel " << p;
    }
  }
  for (const std::uint32_t p : far) ASSERT_EQ(r.exact[p], 1.0f);
}

// The floor pixels beside the hidden box: seen by the camera, within r of the box.
std::vector<std::uint32_t> beside_box(const View& view) {
  std::vector<std::uint32_t> out;
  for (std::size_t p = 0; p < view.pixel_count(); ++p) {
    const glm::vec3 x = view.position[p];
    if (view.valid[p] && std::abs(view.normal[p].y) > 0.99f && x.y < 1e-3f && x.x > -0.5f && x.x < -0.05f && std::abs(x.z) < 0.45f) {
      out.push_back(static_cast<std::uint32_t>(p));
    }
  }
  return out;
}

// Occlusion the box adds beside it, per method: mean AO without the box minus mean AO with it.
struct Gain {
  std::map<Method, double> method;
  double exact = 0.0;
};

Gain box_gain(bool wall, const CompareOptions& options, const std::function<void(Scene&)>& edit = {}, int samples = 128) {
  Scene with = make_hidden_box(true, wall), without = make_hidden_box(false, wall);
  if (edit) edit(with);
  const Exact exact_with(std::move(with), 1.0f, samples), exact_without(std::move(without), 1.0f, samples);
  const Camera camera = exact_with.scene.cameras[0];
  const ViewResult a = compare_view(exact_with.scene, camera, 240, 180, options, std::cref(exact_with), exact_with.hits);
  const ViewResult b = compare_view(exact_without.scene, camera, 240, 180, options, std::cref(exact_without), exact_without.hits);
  const std::vector<std::uint32_t> pixels = beside_box(a.view);
  EXPECT_GT(pixels.size(), 50u);
  EXPECT_EQ(pixels, beside_box(b.view)) << "the box must not change which floor pixels are seen";
  Gain g;
  g.exact = mean_over(b.exact, pixels) - mean_over(a.exact, pixels);
  for (std::size_t i = 0; i < a.methods.size(); ++i) {
    g.method[a.methods[i].method] = mean_over(b.methods[i].ao, pixels) - mean_over(a.methods[i].ao, pixels);
  }
  return g;
}

TEST(Ssao, HiddenBoxSingleLayerMissesItStochasticSeesPartAbufferAndExactSeeAll) {
  CompareOptions options = options_for(1.0f);
  options.methods = {Method::Hbao, Method::HbaoPlus, Method::Vao, Method::SdHbao, Method::SdSvao, Method::Abuffer};
  const Gain hidden = box_gain(true, options);
  const Gain seen = box_gain(false, options);
  // Without the wall every method sees the box.
  for (const auto& [m, gain] : seen.method) EXPECT_GT(gain, 0.02) << compare_method_name(m);
  ASSERT_GT(seen.exact, 0.05);
  // Behind it, the first depth layer is the same with and without the box: nothing changes.
  EXPECT_EQ(hidden.method.at(Method::Hbao), 0.0);
  EXPECT_EQ(hidden.method.at(Method::HbaoPlus), 0.0);
  EXPECT_EQ(hidden.method.at(Method::Vao), 0.0);
  // Share of the box's occlusion each method still sees behind the wall.
  const auto share = [&](Method m) { return hidden.method.at(m) / seen.method.at(m); };
  for (const auto& [m, gain] : hidden.method) {
    std::printf("%-8s box occlusion seen %.4f, behind the wall %.4f (%.0f%%)\n", method_label(m), seen.method.at(m), gain, 100.0 * share(m));
  }
  std::printf("exact    box occlusion seen %.4f, behind the wall %.4f\n", seen.exact, hidden.exact);
  EXPECT_GT(share(Method::SdHbao), 0.05);
  EXPECT_LT(share(Method::SdHbao), 0.95);
  EXPECT_GT(share(Method::SdSvao), 0.05);
  EXPECT_LT(share(Method::SdSvao), 0.95);
  // Every fragment within r is in the A-buffer, and the wall is beyond r: all of it.
  EXPECT_NEAR(share(Method::Abuffer), 1.0, 1e-6);
  EXPECT_GT(share(Method::Abuffer), share(Method::SdHbao));
  // Rays: the wall is beyond r, so exact AO is the same with or without it.
  EXPECT_NEAR(hidden.exact / seen.exact, 1.0, 1e-9);
}

TEST(Ssao, AbufferWeighsOccludersByOpacity) {
  CompareOptions options = options_for(1.0f);
  options.methods = {Method::Abuffer};
  const Gain opaque = box_gain(true, options, {}, 32);
  // The box's triangles are the last 6 x 16 (faces of 4 x 4 cells, two triangles each).
  const auto box_material = [](float opacity) {
    return [opacity](Scene& s) {
      for (std::size_t t = s.triangle_count() - 6 * 4 * 4 * 2; t < s.triangle_count(); ++t) s.material[t] = 1;
      s.material_opacity = {1.0f, opacity};
    };
  };
  const Gain half = box_gain(true, options, box_material(0.5f), 32);
  const Gain clear = box_gain(true, options, box_material(0.0f), 32);
  ASSERT_GT(opaque.method.at(Method::Abuffer), 0.02);
  // With constant falloff a direction's gains add up to opacity x (f(sin h_max) - f(bias)).
  EXPECT_NEAR(half.method.at(Method::Abuffer) / opaque.method.at(Method::Abuffer), 0.5, 1e-4);
  EXPECT_EQ(clear.method.at(Method::Abuffer), 0.0);
}

TEST(Ssao, SubsetTableHoldsEveryMaskOnce) {
  for (int s = 1; s <= 8; ++s) {
    const auto table = subset_table(s);
    ASSERT_EQ(table.size(), static_cast<std::size_t>(s) + 1);
    std::size_t total = 0;
    for (std::size_t r = 0; r < table.size(); ++r) {
      // C(s, r) masks, each with r bits.
      double binomial = 1.0;
      for (std::size_t k = 0; k < r; ++k) binomial = binomial * static_cast<double>(static_cast<std::size_t>(s) - k) / static_cast<double>(k + 1);
      EXPECT_EQ(static_cast<double>(table[r].size()), binomial);
      for (const std::uint32_t m : table[r]) EXPECT_EQ(std::popcount(m), static_cast<int>(r));
      total += table[r].size();
    }
    EXPECT_EQ(total, std::size_t{1} << s);
  }
}

TEST(Ssao, StochasticDepthKeepsEachLayerWithProbabilityAlpha) {
  // Ten parallel squares facing the camera: ten fragments per pixel.
  Scene scene;
  for (int k = 0; k < 10; ++k) {
    const float z = -2.0f - 0.5f * static_cast<float>(k);
    scene.add_triangle({-50.0f, -50.0f, z}, {50.0f, -50.0f, z}, {50.0f, 50.0f, z}, false, 0);
    scene.add_triangle({-50.0f, -50.0f, z}, {50.0f, 50.0f, z}, {-50.0f, 50.0f, z}, false, 0);
  }
  const Camera camera = look_at({0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, -1.0f}, 40.0f);
  const FragmentBuffer fragments = rasterize_fragments(scene, camera, 64, 64);
  for (std::size_t p = 0; p < 64 * 64; ++p) {
    ASSERT_EQ(fragments.at(p).size(), 10u);
    for (std::size_t k = 1; k < 10; ++k) ASSERT_LT(fragments.at(p)[k - 1].depth, fragments.at(p)[k].depth);
  }
  // S = 1: R = floor(alpha + xi) keeps a fragment with probability alpha; a sample is empty when
  // all ten are dropped, (1 - alpha)^10, and holds the first layer with probability alpha.
  StochasticDepthOptions o;
  o.samples = 1;
  o.alpha = 0.2;
  const StochasticDepth map = make_stochastic_depth(fragments, o);
  const double n = 64.0 * 64.0;
  double empty = 0.0, first = 0.0;
  for (std::size_t p = 0; p < 64 * 64; ++p) {
    empty += map.at(p)[0] == kNoDepth;
    first += map.at(p)[0] == fragments.at(p)[0].depth;
  }
  // Binomial standard deviations over 4096 pixels: 0.005 and 0.006; six of them.
  EXPECT_NEAR(empty / n, std::pow(0.8, 10.0), 0.03);
  EXPECT_NEAR(first / n, 0.2, 0.036);
  // alpha = 1: every sample holds the nearest fragment.
  o.samples = 4;
  o.alpha = 1.0;
  const StochasticDepth full = make_stochastic_depth(fragments, o);
  for (std::size_t p = 0; p < 64 * 64; ++p) {
    for (const float w : full.at(p)) ASSERT_EQ(w, fragments.at(p)[0].depth);
  }
  // A stencil leaves the unmarked pixels empty.
  std::vector<std::uint8_t> stencil(64 * 64, 0);
  stencil[100] = 1;
  const StochasticDepth stenciled = make_stochastic_depth(fragments, o, stencil);
  EXPECT_EQ(stenciled.at(100)[0], fragments.at(100)[0].depth);
  EXPECT_EQ(stenciled.at(101)[0], kNoDepth);
  EXPECT_FALSE(check(StochasticDepthOptions{0, 0.2, 0}));
  EXPECT_FALSE(check(StochasticDepthOptions{4, 0.0, 0}));
}

TEST(Ssao, FirstFragmentIsTheGBuffers) {
  const Scene scene = make_room();
  const View view = make_view(scene, scene.cameras[0], 120, 90);
  const FragmentBuffer fragments = rasterize_fragments(scene, scene.cameras[0], 120, 90);
  std::size_t same = 0, seen = 0;
  for (std::size_t p = 0; p < view.pixel_count(); ++p) {
    if (!view.valid[p]) continue;
    ++seen;
    ASSERT_FALSE(fragments.at(p).empty());
    same += fragments.at(p)[0].triangle == view.triangle[p];
  }
  // Ties between triangles that meet at a pixel centre may order either way in float depth.
  EXPECT_GT(static_cast<double>(same), 0.995 * static_cast<double>(seen));
}

TEST(Ssao, VaoHaloModel) {
  VaoSample s;
  s.valid = true;
  s.z_lo = -0.2;
  s.z_hi = 0.6;
  s.height = 1.2;
  const double tau = 0.5, length = 0.8;
  EXPECT_DOUBLE_EQ(unoccupied(s, -1.0, tau), length);  // surface below the column: all open
  EXPECT_DOUBLE_EQ(unoccupied(s, 0.2, tau), 0.4);      // inside: what lies in front of it
  EXPECT_DOUBLE_EQ(unoccupied(s, 0.6, tau), 0.0);
  EXPECT_DOUBLE_EQ(unoccupied(s, 1.2, tau), 0.0);      // the constant area, up to 1 + tau
  EXPECT_NEAR(unoccupied(s, 1.9, tau), 0.4, 1e-12);    // the falloff area, as long as the column
  EXPECT_DOUBLE_EQ(unoccupied(s, 5.0, tau), length);   // far in front: ignored
}

TEST(Ssao, RtSvaoTakesExactAoAtFlaggedPixels) {
  const Exact exact(make_room(), 0.6f, 128);
  CompareOptions options = options_for(0.6f);
  options.methods = {Method::Vao, Method::RtSvao};
  const ViewResult r = compare_view(exact.scene, exact.scene.cameras[0], 96, 72, options, std::cref(exact), exact.hits);
  const MethodResult& rt = result(r, Method::RtSvao);
  ASSERT_GT(rt.flagged, 50u);
  // With the blur off, every pixel is phase 1's VAO or, where flagged, exact AO.
  std::size_t equal_exact = 0;
  for (std::size_t p = 0; p < r.view.pixel_count(); ++p) {
    if (!r.view.valid[p]) continue;
    ASSERT_TRUE(rt.ao[p] == r.exact[p] || rt.ao[p] == result(r, Method::Vao).ao[p]) << p;
    equal_exact += rt.ao[p] == r.exact[p];
  }
  EXPECT_GE(equal_exact, rt.flagged);
}

TEST(Ssao, StereoMetricIsZeroForTheSameViewTwice) {
  const Scene scene = make_room();
  const View view = make_view(scene, scene.cameras[0], 120, 90);
  const Correspondence c = correspond(view, view);
  // The normal check drops pixels whose interpolation would reach across an edge.
  EXPECT_GT(static_cast<double>(c.left.size()), 0.8 * static_cast<double>(c.left_visible));
  std::vector<float> ao(view.pixel_count());
  for (std::size_t p = 0; p < ao.size(); ++p) ao[p] = static_cast<float>(p % 7) / 7.0f;
  const Inconsistency e = inconsistency(c, ao, ao);
  // Bilinear weights at a pixel's own centre, up to the float rounding of the projection.
  EXPECT_LT(e.mean, 1e-5);
}

// Exact AO is view-independent only with keys from the surface point. With pixel keys the eyes
// cast different rays at the same point; with world keys what is left is reprojection alone: the
// error of interpolating a view-independent field between two pixel grids, which one key for the
// whole scene (a cell larger than the scene) measures.
TEST(Ssao, WorldKeysMakeExactAoStereoConsistent) {
  Exact exact(make_room(), 0.6f, 128);
  exact.engine.emplace(std::move(*lut::MaskEngine::build(exact.rays, lut::MaskMode::Lut)));  // exao compare's masks
  CompareOptions options = options_for(0.6f);
  options.methods = {Method::Hbao};
  const auto [left, right] = stereo_cameras(exact.scene.cameras[0], 0.065);
  const auto measure = [&](std::optional<float> cell) {
    options.world_key_cell = cell;
    const ViewResult l = compare_view(exact.scene, left, 240, 180, options, std::cref(exact), exact.hits);
    const ViewResult r = compare_view(exact.scene, right, 240, 180, options, std::cref(exact), exact.hits);
    return inconsistency(correspond(l.view, r.view), l.exact, r.exact);
  };
  const Inconsistency pixel_keys = measure(std::nullopt);
  const Inconsistency world_keys = measure(0.25f * 0.6f);
  const Inconsistency one_key = measure(1e4f);
  EXPECT_GT(world_keys.share, 0.8);
  EXPECT_LT(world_keys.mean, 0.6 * pixel_keys.mean);
  EXPECT_LT(world_keys.mean, 1.3 * one_key.mean + 1e-4);
  EXPECT_LT(world_keys.mean, 1.0 / 255.0);
}

TEST(Ssao, WorldKeyDependsOnlyOnTheCell) {
  EXPECT_EQ(world_key({0.01f, 0.0f, 0.0f}, 1.0f), world_key({0.02f, 0.0f, 0.0f}, 1.0f));
  EXPECT_NE(world_key({0.01f, 0.0f, 0.0f}, 1.0f), world_key({0.9f, 0.0f, 0.0f}, 1.0f));
  // A plane at a round coordinate is not on a cell boundary: float noise keeps one key.
  EXPECT_EQ(world_key({0.3f, 1e-7f, 0.3f}, 0.5f), world_key({0.3f, -1e-7f, 0.3f}, 0.5f));
}

// glTF opacity as core/scene.h states it: BLEND is baseColorFactor's alpha, MASK is 0 or 1 by
// alphaCutoff (default 0.5), OPAQUE is 1.
TEST(Ssao, GltfMaterialsCarryTheirOpacity) {
  test::TempDir dir;
  std::string bin(36, '\0');
  const float corners[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  std::memcpy(bin.data(), corners, sizeof corners);
  test::write_file(dir / "t.bin", bin);
  std::string gltf = R"({"asset":{"version":"2.0"},"buffers":[{"uri":"t.bin","byteLength":36}],
    "bufferViews":[{"buffer":0,"byteLength":36}],
    "accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}],
    "materials":[{"alphaMode":"BLEND","pbrMetallicRoughness":{"baseColorFactor":[1,1,1,0.4]}},
                 {"alphaMode":"MASK","alphaCutoff":0.5,"pbrMetallicRoughness":{"baseColorFactor":[1,1,1,0.3]}},
                 {"alphaMode":"MASK","pbrMetallicRoughness":{"baseColorFactor":[1,1,1,0.6]}},
                 {"pbrMetallicRoughness":{"baseColorFactor":[1,1,1,0.1]}}],
    "meshes":[{"primitives":[{"attributes":{"POSITION":0},"material":0},{"attributes":{"POSITION":0},"material":1},
                             {"attributes":{"POSITION":0},"material":2},{"attributes":{"POSITION":0},"material":3}]}],
    "nodes":[{"mesh":0}],"scenes":[{"nodes":[0]}],"scene":0})";
  test::write_file(dir / "t.gltf", gltf);
  const Result<Scene> scene = load_scene((dir / "t.gltf").string());
  ASSERT_TRUE(scene) << scene.error().message;
  ASSERT_EQ(scene->triangle_count(), 4u);
  EXPECT_FLOAT_EQ(scene->opacity(0), 0.4f);
  EXPECT_FLOAT_EQ(scene->opacity(1), 0.0f);
  EXPECT_FLOAT_EQ(scene->opacity(2), 1.0f);
  EXPECT_FLOAT_EQ(scene->opacity(3), 1.0f);
  EXPECT_FLOAT_EQ(make_room().opacity(0), 1.0f);
}

TEST(Ssao, AlphaBlendModeTestIsOpaqueWithoutItsTextures) {
  const auto path = test::real_scene("AlphaBlendModeTest/glTF/AlphaBlendModeTest.gltf");
  EXAO_REQUIRE_SCENE(path);
  const Result<Scene> scene = load_scene(path.string());
  ASSERT_TRUE(scene) << scene.error().message;
  // Its cut-outs are in the (absent) textures; every baseColorFactor alpha is 1.
  ASSERT_EQ(scene->material_opacity.size(), 6u);
  for (const float a : scene->material_opacity) EXPECT_EQ(a, 1.0f);
}

TEST(Ssao, BadOptionsAreRefusedWithTheirName) {
  EXPECT_FALSE(parse_methods("hbao,foo"));
  EXPECT_NE(parse_methods("hbao,foo").error().message.find("foo"), std::string::npos);
  EXPECT_FALSE(parse_methods("hbao,hbao"));
  EXPECT_FALSE(parse_methods(""));
  EXPECT_EQ(parse_methods("hbao+,abuffer")->size(), 2u);
  EXPECT_EQ(*parse_methods("all"), all_methods());
  EXPECT_EQ(all_methods().size(), 15u);
  EXPECT_FALSE(parse_methods("all,hbao"));
  for (const Method m : all_methods()) EXPECT_EQ(parse_methods(compare_method_name(m))->front(), m);
  CompareOptions o = options_for(1.0f);
  o.hbao.directions = 0;
  EXPECT_NE(check(o).error().message.find("directions"), std::string::npos);
  o = options_for(1.0f);
  o.vao.thickness = 2.0;
  EXPECT_NE(check(o).error().message.find("thickness"), std::string::npos);
  o = options_for(1.0f);
  o.settings.blur_radius = -1;
  EXPECT_NE(check(o).error().message.find("blur"), std::string::npos);
  o = options_for(1.0f);
  o.multiview.angle_degrees = 0.0;
  EXPECT_NE(check(o).error().message.find("secondary view angle"), std::string::npos);
  o = options_for(1.0f);
  o.stereo_ipd = 0.0;
  EXPECT_NE(check(o).error().message.find("stereo eye distance"), std::string::npos);
  EXPECT_FALSE(check(ListCompression{0, true}));
}


// ---- Seed 003: stereo-aware HBAO+ (Sec. 3) ----

// Sec. 3.2: a right pixel that passes the back-check takes the left value exactly; the others are
// evaluated from scratch. Sec. 3.1-3.3 as a whole: stereo HBAO+ is more consistent between the
// eyes than mono HBAO+ run on each eye (their Fig. 10 A against F), in both filter forms.
TEST(Ssao, StereoHbaoPlusIsMoreConsistentThanMonoHbaoPlus) {
  const Exact exact(make_room(), 0.6f, 32);
  CompareOptions options = options_for(0.6f);
  options.settings.blur_radius = 4;
  options.methods = {Method::HbaoPlus, Method::StereoHbaoPlus, Method::StereoHbaoPlus2d};
  const auto eyes = stereo_cameras(exact.scene.cameras[0], 0.065);
  options.stereo_eyes = eyes;
  const ViewResult l = compare_view(exact.scene, eyes.first, 160, 120, options, std::cref(exact), exact.hits);
  const ViewResult r = compare_view(exact.scene, eyes.second, 160, 120, options, std::cref(exact), exact.hits);
  const StereoObscurance raw = stereo_hbao_plus(l.view, r.view, options.settings, options.hbao_plus);
  ASSERT_GT(raw.reprojected, 10000u);
  ASSERT_GT(raw.holes, 0u);
  for (std::size_t q = 0; q < r.view.pixel_count(); ++q) {
    if (!r.view.valid[q] || !raw.right_both[q]) continue;
    const std::int64_t p = nearest_pixel(l.view, glm::dvec3(r.view.position[q]));
    ASSERT_EQ(raw.right[q], raw.left[static_cast<std::size_t>(p)]) << q;
  }
  const Correspondence c = correspond(l.view, r.view);
  const auto e = [&](Method m) { return inconsistency(c, result(l, m).ao, result(r, m).ao).mean; };
  std::printf("stereo E: HBAO+ %.5f, S-HBAO+ %.5f, S-HBAO+ 2D %.5f\n", e(Method::HbaoPlus), e(Method::StereoHbaoPlus), e(Method::StereoHbaoPlus2d));
  EXPECT_LT(e(Method::StereoHbaoPlus), e(Method::HbaoPlus));
  EXPECT_LT(e(Method::StereoHbaoPlus2d), e(Method::HbaoPlus));
}

// With both eyes at one point every sample is Case A with two equal contributions: the stereo
// estimate is mono HBAO+ (up to a sample whose projection rounds to the other side of a pixel edge).
TEST(Ssao, StereoEstimateWithOneEyeTwiceIsMonoHbaoPlus) {
  const Scene scene = make_room();
  const View view = make_view(scene, scene.cameras[0], 120, 90);
  Settings settings;
  settings.radius = 0.6;
  const HbaoPlusOptions o;
  const std::vector<float> mono = hbao_plus(view, settings, o);
  const StereoObscurance stereo = stereo_hbao_plus(view, view, settings, o);
  std::size_t seen = 0, same = 0;
  for (std::size_t p = 0; p < view.pixel_count(); ++p) {
    if (!view.valid[p]) continue;
    ++seen;
    same += std::abs(stereo.left[p] - mono[p]) < 1e-5f;
    EXPECT_EQ(stereo.right[p], stereo.left[p]);  // every pixel passes the back-check onto itself
  }
  EXPECT_EQ(stereo.holes, 0u);
  EXPECT_GT(static_cast<double>(same), 0.99 * static_cast<double>(seen));
}

// Fig. 6 D: w = smoothstep(0.5 - eta, 0.5, alpha); and a constant field stays constant.
TEST(Ssao, StereoFilterFollowsFigure6) {
  EXPECT_EQ(stereo_filter_weight(0.5, 0.05), 1.0);
  EXPECT_EQ(stereo_filter_weight(0.9, 0.05), 1.0);
  EXPECT_EQ(stereo_filter_weight(0.45, 0.05), 0.0);
  EXPECT_EQ(stereo_filter_weight(0.1, 0.05), 0.0);
  EXPECT_NEAR(stereo_filter_weight(0.475, 0.05), 0.5, 1e-12);
  for (double a = 0.45; a < 0.5; a += 0.005) EXPECT_LE(stereo_filter_weight(a, 0.05), stereo_filter_weight(a + 0.005, 0.05));
  const Scene scene = make_room();
  const auto [left_camera, right_camera] = stereo_cameras(scene.cameras[0], 0.065);
  const View left = make_view(scene, left_camera, 80, 60), right = make_view(scene, right_camera, 80, 60);
  for (const StereoFilterForm form : {StereoFilterForm::Full, StereoFilterForm::Separable}) {
    std::vector<float> a(left.pixel_count(), 0.25f), b(right.pixel_count(), 0.25f);
    stereo_filter(left, right, a, b, StereoFilterOptions{4, 0.05, form});
    for (std::size_t p = 0; p < a.size(); ++p) {
      ASSERT_NEAR(a[p], 0.25f, 1e-6f);
      ASSERT_NEAR(b[p], 0.25f, 1e-6f);
    }
  }
}

// ---- Seed 000: SD-HBAO+ and its multi-view form (Sec. 3.2, 3.4, Alg. 3) ----

// A map with alpha = 1 holds the first layer in every sample: SD-HBAO+ is then HBAO+.
TEST(Ssao, SdHbaoPlusWithEveryFirstLayerIsHbaoPlus) {
  const Scene scene = make_room();
  const View view = make_view(scene, scene.cameras[0], 120, 90);
  const FragmentBuffer fragments = rasterize_fragments(scene, scene.cameras[0], 120, 90);
  const StochasticDepth first = make_stochastic_depth(fragments, StochasticDepthOptions{2, 1.0, 0});
  Settings settings;
  settings.radius = 0.6;
  const HbaoPlusOptions o;
  const std::vector<float> mono = hbao_plus(view, settings, o), sd = sd_hbao_plus(view, first, settings, o);
  for (std::size_t p = 0; p < view.pixel_count(); ++p) ASSERT_NEAR(sd[p], mono[p], 1e-4f) << p;
}

// Seed 000's Fig. 3: the box's +X side is edge-on to the main camera and leaves no fragment,
// so no single-view method sees it; the secondary view does (Alg. 3). Occlusion the box adds to
// the floor beside that side (mean AO without the box minus with it); Alg. 3's max over the
// cameras only ever adds occlusion.
TEST(Ssao, MultiViewSeesTheSideSeenEdgeOn) {
  const Exact with(make_grazing_box(true), 1.0f, 128), without(make_grazing_box(false), 1.0f, 128);
  CompareOptions options = options_for(1.0f);
  options.methods = {Method::HbaoPlus, Method::SdHbaoPlus, Method::MvSdHbaoPlus, Method::Abuffer};
  const Camera camera = with.scene.cameras[0];
  const ViewResult a = compare_view(with.scene, camera, 240, 180, options, std::cref(with), with.hits);
  const ViewResult b = compare_view(without.scene, camera, 240, 180, options, std::cref(without), without.hits);
  // No fragment of the side (triangles 6 and 7: floor, +Z, -Z come first).
  const FragmentBuffer fragments = rasterize_fragments(with.scene, camera, 240, 180);
  for (const Fragment& f : fragments.fragments) ASSERT_TRUE(f.triangle != 6 && f.triangle != 7);
  std::vector<std::uint32_t> beside;
  for (std::size_t p = 0; p < a.view.pixel_count(); ++p) {
    const glm::vec3 x = a.view.position[p];
    if (a.view.valid[p] && a.view.normal[p].y > 0.99f && x.y < 1e-3f && x.x > 1.02f && x.x < 1.4f && x.z > -2.6f && x.z < -0.6f) {
      beside.push_back(static_cast<std::uint32_t>(p));
    }
  }
  ASSERT_GT(beside.size(), 100u);
  const double exact_gain = mean_over(b.exact, beside) - mean_over(a.exact, beside);
  const auto gain = [&](Method m) { return (mean_over(result(b, m).ao, beside) - mean_over(result(a, m).ao, beside)) / exact_gain; };
  std::printf("grazing side (%zu floor pixels): exact gain %.4f; share seen: HBAO+ %.3f, SD-HBAO+ %.3f, A-buffer %.3f, MV-SD-HBAO+ %.3f\n",
              beside.size(), exact_gain, gain(Method::HbaoPlus), gain(Method::SdHbaoPlus), gain(Method::Abuffer), gain(Method::MvSdHbaoPlus));
  ASSERT_GT(exact_gain, 0.1);
  EXPECT_LT(gain(Method::HbaoPlus), 0.1);
  EXPECT_LT(gain(Method::SdHbaoPlus), 0.1);
  EXPECT_GT(gain(Method::MvSdHbaoPlus), 3.0 * std::max(gain(Method::SdHbaoPlus), 0.05));
  for (std::size_t p = 0; p < a.view.pixel_count(); ++p) ASSERT_LE(result(a, Method::MvSdHbaoPlus).ao[p], result(a, Method::SdHbaoPlus).ao[p]) << p;
}

// ---- Seed 004: list compression (Sec. III-B) and transparent receivers (Eq. 2-4) ----

TEST(Ssao, ListCompressionKeepsShortListsAndFollowsEquation5) {
  const Scene room = make_room();
  const View view = make_view(room, room.cameras[0], 96, 72);
  const FragmentBuffer fragments = rasterize_fragments(room, room.cameras[0], 96, 72);
  std::size_t longest = 0;
  for (std::size_t p = 0; p < view.pixel_count(); ++p) longest = std::max(longest, fragments.at(p).size());
  ASSERT_GT(longest, 2u);
  // m at least every list's length: nothing changes, and neither does the AO.
  const FragmentBuffer same = compress_fragments(fragments, view, room, ListCompression{static_cast<int>(longest), true});
  ASSERT_EQ(same.offset, fragments.offset);
  Settings settings;
  settings.radius = 0.6;
  EXPECT_EQ(abuffer_ao(view, same, room, settings, HbaoOptions{}), abuffer_ao(view, fragments, room, settings, HbaoOptions{}));
  // Ten parallel squares, opacities alternating 1, 0.2, 1, 0.2, ...: with the front half kept
  // (m = 4: two), Eq. 5 drops the least alpha (1 - z) of the back, the transparent far ones.
  Scene stack;
  for (int k = 0; k < 10; ++k) {
    const float z = -2.0f - 0.5f * static_cast<float>(k);
    stack.add_triangle({-50.0f, -50.0f, z}, {50.0f, -50.0f, z}, {50.0f, 50.0f, z}, false, k % 2);
    stack.add_triangle({-50.0f, -50.0f, z}, {50.0f, 50.0f, z}, {-50.0f, 50.0f, z}, false, k % 2);
  }
  stack.material_opacity = {1.0f, 0.2f};
  const Camera camera = look_at({0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, -1.0f}, 40.0f);
  const View stack_view = make_view(stack, camera, 16, 16);
  const FragmentBuffer layers = rasterize_fragments(stack, camera, 16, 16);
  const FragmentBuffer four = compress_fragments(layers, stack_view, stack, ListCompression{4, true});
  const FragmentBuffer whole = compress_fragments(layers, stack_view, stack, ListCompression{4, false});
  for (std::size_t p = 0; p < 16 * 16; ++p) {
    ASSERT_EQ(layers.at(p).size(), 10u);
    ASSERT_EQ(four.at(p).size(), 4u);
    // Front half: layers 0 and 1; then the opaque ones nearest first among the rest (2, 4).
    const float depth[4] = {layers.at(p)[0].depth, layers.at(p)[1].depth, layers.at(p)[2].depth, layers.at(p)[4].depth};
    for (std::size_t k = 0; k < 4; ++k) ASSERT_EQ(four.at(p)[k].depth, depth[k]) << p << " " << k;
    // Over the whole list the transparent layer 1 goes too: the four nearest opaque layers.
    for (std::size_t k = 0; k < 4; ++k) ASSERT_EQ(whole.at(p)[k].depth, layers.at(p)[2 * k].depth) << p << " " << k;
  }
}

// On opaque geometry the transparent-receiver form is the opaque A-buffer (the first fragment is
// the G-buffer's receiver). A pane of opacity alpha over the floor: alpha = 0 is the floor alone,
// alpha = 1 the pane alone, and in between (Eq. 2-4 with the blend) strictly between the two.
TEST(Ssao, TransparentReceiversBlendByOpacity) {
  const Scene room = make_room();
  const View view = make_view(room, room.cameras[0], 96, 72);
  const FragmentBuffer fragments = rasterize_fragments(room, room.cameras[0], 96, 72);
  Settings settings;
  settings.radius = 0.6;
  const std::vector<float> opaque = abuffer_ao(view, fragments, room, settings, HbaoOptions{});
  const std::vector<float> oit = abuffer_oit_ao(view, fragments, room, settings, HbaoOptions{});
  std::size_t same = 0, seen = 0;
  for (std::size_t p = 0; p < view.pixel_count(); ++p) {
    if (!view.valid[p]) continue;
    ++seen;
    same += opaque[p] == oit[p];
  }
  EXPECT_GT(static_cast<double>(same), 0.995 * static_cast<double>(seen));  // float ties between triangles aside

  // The hidden box's floor and box, and a pane (material 1) facing the camera at z = 3, more
  // than r from everything: the pane is open on both sides and occludes nothing, so Eq. 2-4's
  // blend alone is left: alpha * 1 + (1 - alpha) * AO of what is behind it.
  const auto with_pane = [](float alpha) {
    Scene s = make_hidden_box(true, false);
    s.add_triangle({-1.5f, 0.8f, 3.0f}, {1.5f, 0.8f, 3.0f}, {1.5f, 2.5f, 3.0f}, false, 1);
    s.add_triangle({-1.5f, 0.8f, 3.0f}, {1.5f, 2.5f, 3.0f}, {-1.5f, 2.5f, 3.0f}, false, 1);
    s.material_opacity = {1.0f, alpha};
    return s;
  };
  const Scene none = make_hidden_box(true, false);
  const Camera camera = none.cameras[0];
  const auto ao = [&](const Scene& s) {
    const View v = make_view(s, camera, 120, 90);
    return abuffer_oit_ao(v, rasterize_fragments(s, camera, 120, 90), s, settings, HbaoOptions{});
  };
  const Scene half = with_pane(0.5f);
  const View v_half = make_view(half, camera, 120, 90), v_none = make_view(none, camera, 120, 90);
  const std::vector<float> a0 = ao(with_pane(0.0f)), a5 = ao(half), a1 = ao(with_pane(1.0f)), behind = ao(none);
  std::size_t compared = 0, dark = 0;
  for (std::size_t p = 0; p < v_half.pixel_count(); ++p) {
    if (!v_none.valid[p] || v_half.triangle[p] < none.triangle_count()) continue;  // pixels the pane covers
    ++compared;
    ASSERT_NEAR(a0[p], behind[p], 1e-4f) << p;  // opacity 0: not there
    ASSERT_EQ(a1[p], 1.0f) << p;                 // opaque: the open pane alone
    ASSERT_NEAR(a5[p], 0.5f * 1.0f + 0.5f * a0[p], 1e-5f) << p;
    dark += a0[p] < 0.9f;
  }
  ASSERT_GT(compared, 500u);
  EXPECT_GT(dark, 20u);  // the pane covers some occluded floor (the box's contact shadow)
}

// ---- Seed 001: RT-SVAO with column rays (Sec. 3.8) ----

// Rays only revisit flagged samples and can only lower a sample's unoccupied length (a_i is a
// minimum over the depth buffer's value and the rays'): unflagged pixels are VAO's bit for bit,
// flagged ones at most VAO's. Behind the hidden box's wall VAO sees nothing of the box, while the
// flagged columns reach it; with every pixel flagged, exao's first form is exact AO.
TEST(Ssao, RtSvaoRaysRevisitOnlyFlaggedSamplesAndSeeTheHiddenBox) {
  const Exact exact(make_room(), 0.6f, 32);
  const View view = make_view(exact.scene, exact.scene.cameras[0], 96, 72);
  Settings settings;
  settings.radius = 0.6;
  const VaoResult phase1 = vao(view, settings, VaoOptions{});
  const std::vector<float> rays = rt_svao_columns(view, phase1, settings, VaoOptions{}, exact.hits);
  std::size_t flagged = 0, darker = 0;
  for (std::size_t p = 0; p < view.pixel_count(); ++p) {
    if (!phase1.flags[p]) {
      ASSERT_EQ(rays[p], phase1.ao[p]) << p;
      continue;
    }
    ++flagged;
    ASSERT_LE(rays[p], phase1.ao[p] + 1e-6f) << p;
    darker += rays[p] < phase1.ao[p] - 1e-4f;
  }
  ASSERT_GT(flagged, 50u);
  EXPECT_GT(darker, 0u);
  VaoResult all = phase1;
  std::vector<float> exact_all = exact(view.receivers.receivers);
  for (const std::uint32_t p : view.receivers.pixel) all.flags[p] = 1;
  const std::vector<float> first_form = rt_svao(all, exact_all);
  for (std::size_t k = 0; k < view.receivers.pixel.size(); ++k) ASSERT_EQ(first_form[view.receivers.pixel[k]], exact_all[k]);

  CompareOptions options = options_for(1.0f);
  options.methods = {Method::Vao, Method::RtSvaoRays};
  const Gain hidden = box_gain(true, options, {}, 32), seen = box_gain(false, options, {}, 32);
  std::printf("RT-SVAO rays: box seen %.4f, behind the wall %.4f; VAO %.4f, %.4f\n", seen.method.at(Method::RtSvaoRays),
              hidden.method.at(Method::RtSvaoRays), seen.method.at(Method::Vao), hidden.method.at(Method::Vao));
  EXPECT_EQ(hidden.method.at(Method::Vao), 0.0);
  EXPECT_GT(hidden.method.at(Method::RtSvaoRays), 0.5 * seen.method.at(Method::Vao));
}

}  // namespace
}  // namespace exao::ssao
