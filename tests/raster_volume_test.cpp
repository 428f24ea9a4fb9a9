// Influence volumes (raster/influence_volume.h) are conservative, shape by shape: for random
// triangles (ordinary, slivers, needles; one- and two-sided; small and large next to r) and
// random points p that a triangle's mask may need (within r + eps + G of it, and not behind a
// one-sided triangle by more than eps + G), a camera is put anywhere on a line through p (outside
// the volume, inside it, nearly touching it) with p exactly on the centre pixel's ray. Some far
// face of the volume must cover that pixel centre and pass the inverted depth test at p.

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/camera.h"
#include "core/scene.h"
#include "lut/triangle_set.h"
#include "raster/fragment_tests.h"
#include "raster/gbuffer.h"
#include "raster/influence_volume.h"
#include "raster/rasterizer.h"
#include "raster/screen_polygon.h"

namespace exao::raster {
namespace {

enum class Kind { Ordinary, Sliver, Needle };

glm::vec3 random_unit(std::mt19937& random) {
  std::normal_distribution<float> normal;
  glm::vec3 v;
  do v = {normal(random), normal(random), normal(random)};
  while (glm::length(v) < 1e-3f);
  return glm::normalize(v);
}

// A random point of triangle (a, b, c), vertices and edges included now and then.
glm::vec3 point_on(std::mt19937& random, const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) {
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  float s = u(random), t = u(random);
  if (s + t > 1.0f) s = 1.0f - s, t = 1.0f - t;
  switch (std::uniform_int_distribution<int>(0, 4)(random)) {
    case 0: return a;
    case 1: return a + s * (b - a);  // on an edge
    default: return a + s * (b - a) + t * (c - a);
  }
}

struct Counts {
  int trials = 0;
  int uncovered = 0;
  int shape[3] = {0, 0, 0};
  int camera_inside = 0;
};

// `shrink` (a fraction of r) makes the volumes too small, to see that the check notices.
Counts check_volumes(Kind kind, float alpha, std::uint32_t seed, float shrink = 0.0f) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  const float r = 0.5f, eps = 1e-3f;
  ShadowRays rays;
  rays.radius = r;
  rays.origin_offset = eps;
  Counts counts;
  for (int trial = 0; trial < 20000; ++trial) {
    // The triangle, somewhere off the origin so coordinates carry some rounding.
    const glm::vec3 offset = glm::vec3(3.0f, -2.0f, 5.0f) + 2.0f * random_unit(random);
    const float size = std::array<float, 4>{0.02f, 0.1f, 0.6f, 3.0f}[std::uniform_int_distribution<int>(0, 3)(random)];
    glm::vec3 a = offset + size * random_unit(random), b = offset + size * random_unit(random), c;
    if (kind == Kind::Ordinary) {
      c = offset + size * random_unit(random);
    } else if (kind == Kind::Sliver) {  // an angle of ~179.98 degrees at c
      c = 0.5f * (a + b) + 2e-4f * glm::length(b - a) * glm::normalize(glm::cross(b - a, random_unit(random)));
    } else {  // a needle: ~1e-7 radians at a
      c = a + 1.3f * (b - a) + 1.5e-7f * glm::length(b - a) * glm::normalize(glm::cross(b - a, random_unit(random)));
    }
    Scene scene;
    const bool one_sided = u(random) < 0.5f;
    if (!scene.add_triangle(a, b, c, !one_sided, -1)) continue;
    const lut::TriangleSet triangles = lut::TriangleSet::build(scene);

    // A point the triangle's mask may need.
    const glm::vec3 n = glm::normalize(glm::cross(b - a, c - a));
    glm::vec3 p;
    for (;;) {
      const float length = (u(random) < 0.5f ? 1.0f : u(random)) * (r + eps);
      p = point_on(random, a, b, c) + length * random_unit(random);
      if (!one_sided || !(glm::dot(n, p - a) < -eps)) break;  // a NaN normal (float needle): any side
    }

    // A camera on a line through p, looking at it: the centre pixel of an odd-sized image has
    // its ray along the camera's forward axis, through p.
    const float distance = std::array<float, 6>{0.003f, 0.05f, 0.4f, 1.0f, 4.0f, 60.0f}[std::uniform_int_distribution<int>(0, 5)(random)];
    const glm::vec3 eye = p - distance * random_unit(random);
    const Camera camera = look_at(eye, p, 20.0f + 130.0f * u(random));
    const int width = 101, height = 75;
    const double scale = scene_scale(scene, eye);
    const double near = 1e-6 * scale;
    const Projection projection = Projection::make(camera, width, height, near);
    VolumeParams params = make_volume_params(rays, scale, alpha, near);
    params.grow -= shrink * r;

    InfluenceVolume volume;
    const bool built = build_volume(triangles, 0, params, projection, volume);
    EXPECT_TRUE(built) << "trial " << trial;
    if (!built) continue;
    ++counts.trials;
    ++counts.shape[static_cast<int>(volume.shape)];
    counts.camera_inside += glm::length(eye - triangles.centre[0]) < triangles.radius[0] + r;

    bool covered = false;
    for (int f = 0; f < volume.face_count && !covered; ++f) {
      const auto& face = volume.face[static_cast<std::size_t>(f)];
      std::array<ClipVertex, ScreenPolygon::kMaxInput> clip;
      for (int i = 0; i < face.count; ++i) clip[static_cast<std::size_t>(i)] = volume.clip[volume.index[static_cast<std::size_t>(face.first + i)]];
      PolygonRaster raster;
      if (!raster.setup(make_screen_polygon(projection, {clip.data(), face.count}))) continue;
      covered = raster.covers(width / 2, height / 2) && passes_depth_test(face.depth, p - eye, params.slack);
    }
    if (covered) continue;
    ++counts.uncovered;
    if (shrink == 0.0f) {
      ADD_FAILURE() << "trial " << trial << ": shape " << static_cast<int>(volume.shape) << ", "
                    << (one_sided ? "one" : "two") << "-sided, size " << size << ", eye " << distance
                    << " from the point";
    }
  }
  return counts;
}

TEST(RasterVolume, PrismsAndBillboardsHoldTheirInfluence) {
  for (const float alpha : {0.2f, 1e-6f, 1e6f}) {
    const Counts c = check_volumes(Kind::Ordinary, alpha, 11);
    EXPECT_GT(c.trials, 19000);
    EXPECT_GT(c.camera_inside, 1000);
    if (alpha < 1.0f) {
      EXPECT_GT(c.shape[static_cast<int>(VolumeShape::Prism)], 5000);
    }
    if (alpha > 0.1f) {
      EXPECT_GT(c.shape[static_cast<int>(VolumeShape::Billboard)], 2000);
    }
  }
}

TEST(RasterVolume, SliversAndNeedlesHoldTheirInfluence) {
  const Counts slivers = check_volumes(Kind::Sliver, 0.2f, 12);
  EXPECT_GT(slivers.trials, 19000);
  for (const float alpha : {0.2f, 1e6f}) {
    const Counts needles = check_volumes(Kind::Needle, alpha, 13);
    EXPECT_GT(needles.trials, 15000);
    EXPECT_GT(needles.shape[static_cast<int>(VolumeShape::Box)], 2000);
  }
}

// The check has teeth: volumes 1% of r too small leave points uncovered, for every shape.
TEST(RasterVolume, ShrunkVolumesAreCaught) {
  EXPECT_GT(check_volumes(Kind::Ordinary, 1e-6f, 11, 0.01f).uncovered, 10);  // prisms
  EXPECT_GT(check_volumes(Kind::Ordinary, 1e6f, 11, 0.01f).uncovered, 10);   // billboards
  EXPECT_GT(check_volumes(Kind::Needle, 0.2f, 13, 0.01f).uncovered, 10);     // boxes
}

}  // namespace
}  // namespace exao::raster
