// The raster backend's primary visibility (raster/gbuffer.h) against Embree's primary rays, and
// the rasterizer's fill rule: every pixel centre of a watertight mesh is covered exactly once.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <optional>
#include <random>

#include "core/builtin_scenes.h"
#include "core/camera.h"
#include "core/embree_reference.h"
#include "io/polygon_soup_loader.h"
#include "core/pixel_receivers.h"
#include "raster/gbuffer.h"
#include "raster/rasterizer.h"
#include "raster/screen_polygon.h"
#include "tests/test_support.h"

namespace exao::raster {
namespace {

// --- Fill rule ---------------------------------------------------------------------------------

// A grid mesh over (and beyond) a small image, vertices jittered, a third of them snapped onto
// pixel centres and some edges along pixel rows and columns: each pixel centre must be covered by
// exactly one triangle, whichever winding each triangle has.
TEST(RasterFillRule, WatertightMeshCoversEveryPixelCentreOnce) {
  const int width = 37, height = 29;
  Camera camera = look_at({0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, -1.0f}, 60.0f);
  const Projection projection = Projection::make(camera, width, height, 1e-3);
  std::mt19937 random(7);
  std::uniform_real_distribution<double> jitter(-0.45, 0.45);
  std::uniform_int_distribution<int> kind(0, 2);
  const int nx = 15, ny = 12;
  // Grid points in pixels, from -3 to size + 3 pixels.
  std::vector<ClipVertex> grid(static_cast<std::size_t>(nx * ny));
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      double px = -3.0 + (width + 6.0) * i / (nx - 1), py = -3.0 + (height + 6.0) * j / (ny - 1);
      switch (kind(random)) {
        case 0: px = std::floor(px) + 0.5; py = std::floor(py) + 0.5; break;  // on a pixel centre
        case 1: px += jitter(random); py += jitter(random); break;
        default: py = std::floor(py) + 0.5; break;  // on a row of centres
      }
      // Back to clip space at depth w (any w > 0 projects to the same pixel).
      const double w = 1.0 + 0.1 * i;
      grid[static_cast<std::size_t>(j * nx + i)] = {(2.0 * px / width - 1.0) * w, (1.0 - 2.0 * py / height) * w, w};
    }
  }
  std::vector<int> covered(static_cast<std::size_t>(width * height), 0);
  std::bernoulli_distribution flip(0.5);
  for (int j = 0; j + 1 < ny; ++j) {
    for (int i = 0; i + 1 < nx; ++i) {
      const ClipVertex a = grid[static_cast<std::size_t>(j * nx + i)], b = grid[static_cast<std::size_t>(j * nx + i + 1)];
      const ClipVertex c = grid[static_cast<std::size_t>((j + 1) * nx + i)], d = grid[static_cast<std::size_t>((j + 1) * nx + i + 1)];
      const bool diagonal = flip(random);
      std::array<std::array<ClipVertex, 3>, 2> tris = diagonal ? std::array<std::array<ClipVertex, 3>, 2>{{{a, b, d}, {a, d, c}}}
                                                                : std::array<std::array<ClipVertex, 3>, 2>{{{a, b, c}, {b, d, c}}};
      for (auto& tri : tris) {
        if (flip(random)) std::swap(tri[1], tri[2]);  // either winding
        PolygonRaster raster;
        if (!raster.setup(make_screen_polygon(projection, tri))) continue;
        for (int y = raster.y0(); y <= raster.y1(); ++y) {
          raster.spans(y, 0, width - 1, [&](int xa, int xb) {
            for (int x = xa; x <= xb; ++x) {
              ++covered[static_cast<std::size_t>(y * width + x)];
              EXPECT_TRUE(raster.covers(x, y));
            }
          });
        }
      }
    }
  }
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) EXPECT_EQ(covered[static_cast<std::size_t>(y * width + x)], 1) << x << "," << y;
  }
}

// A thin convex hexagon (a sliver's prism face, seen from afar) whose two vertices snap one
// subpixel apart: the tiny edge's snapped direction is arbitrary, and as a half-plane it would cut
// the polygon in two. The polygon is drawn as a fan instead and covers the centre inside it.
TEST(RasterFillRule, SnappedTinyEdgeDoesNotCutThePolygon) {
  const int width = 101, height = 75;
  const Projection projection = Projection::make(look_at({0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, -1.0f}, 60.0f), width, height, 1e-3);
  const double pixels[6][2] = {{49.9585, 38.3362}, {49.749, 38.1858},   {50.6455, 36.9243},
                               {50.856, 37.073},   {50.40752, 37.7046}, {50.40751, 37.7048}};
  std::vector<ClipVertex> clip;
  for (const auto& p : pixels) clip.push_back({2.0 * p[0] / width - 1.0, 1.0 - 2.0 * p[1] / height, 1.0});
  PolygonRaster raster;
  ASSERT_TRUE(raster.setup(make_screen_polygon(projection, clip)));
  EXPECT_GT(raster.parts(), 1);  // not convex once snapped: a fan
  EXPECT_TRUE(raster.covers(50, 37));  // centre (50.5, 37.5) is inside by ~0.05 pixel
}

// --- Against Embree ----------------------------------------------------------------------------

// Angular distance (radians) from the ray (eye, unit d) to the nearest edge plane of triangle t:
// near zero when the pixel centre lies on the triangle's projected outline.
double edge_angle(const Scene& scene, std::uint32_t t, const glm::vec3& eye, const glm::vec3& d) {
  const auto tri = scene.triangle(t);
  double nearest = 1e30;
  for (int k = 0; k < 3; ++k) {
    const glm::dvec3 a = glm::dvec3(tri[static_cast<std::size_t>(k)]) - glm::dvec3(eye);
    const glm::dvec3 b = glm::dvec3(tri[static_cast<std::size_t>((k + 1) % 3)]) - glm::dvec3(eye);
    const glm::dvec3 n = glm::cross(a, b);
    const double length = glm::length(n);
    if (length > 0.0) nearest = std::min(nearest, std::abs(glm::dot(glm::dvec3(d), n)) / length);
  }
  return nearest;
}

bool share_vertex(const Scene& scene, std::uint32_t s, std::uint32_t t) {
  const auto a = scene.triangle(s), b = scene.triangle(t);
  for (const auto& p : a) {
    for (const auto& q : b) {
      if (p == q) return true;
    }
  }
  return false;
}

struct Agreement {
  std::size_t pixels = 0, same = 0, on_edge = 0, same_depth = 0, unexplained = 0, shared = 0;
};

// Triangle ids of the raster G-buffer against Embree's closest hits. A pixel may differ only
// where its centre is within float rounding of an outline of either triangle (an edge, shared or
// a silhouette) or where both hits are at the same depth (coplanar or crossing surfaces).
Agreement compare_with_embree(const Scene& scene, const Camera& camera, int width, int height) {
  auto embree = EmbreeScene::build(scene);
  EXPECT_TRUE(embree);
  const GBuffer g = rasterize_gbuffer(scene, camera, width, height);
  // Float rounding of the projection and the 1/4096-pixel snap are ~1e-4 pixel; Embree's edge
  // tests round at a few 1e-7 relative. 2e-3 of a pixel's angle is well above both.
  const double pixel_angle = 2.0 * std::tan(0.5 * camera.yfov) / height;
  const double edge_tolerance = 2e-3 * pixel_angle;
  Agreement a;
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const std::size_t p = static_cast<std::size_t>(y * width + x);
      const glm::vec3 d = pixel_ray(camera, width, height, x, y);
      const auto hit = embree->closest_hit(camera.eye, d);
      const std::uint32_t ours = g.triangle[p];
      const std::uint32_t theirs = hit ? hit->triangle : kNoTriangle;
      ++a.pixels;
      if (ours == theirs) {
        ++a.same;
        continue;
      }
      const bool edge = (ours != kNoTriangle && edge_angle(scene, ours, camera.eye, d) < edge_tolerance) ||
                        (theirs != kNoTriangle && edge_angle(scene, theirs, camera.eye, d) < edge_tolerance);
      bool depth = false;
      if (ours != kNoTriangle && theirs != kNoTriangle) {
        const double our_distance = 1.0 / g.inverse_depth[p] / glm::dot(d, camera.forward);
        depth = std::abs(our_distance - hit->distance) <= 1e-5 * hit->distance;
        a.shared += share_vertex(scene, ours, theirs);
      }
      a.on_edge += edge;
      a.same_depth += !edge && depth;
      if (!edge && !depth) {
        ++a.unexplained;
        ADD_FAILURE() << "pixel " << x << "," << y << ": raster " << ours << ", embree " << theirs
                      << (hit ? " at " + std::to_string(hit->distance) : std::string());
      }
    }
  }
  const double share = double(a.same) / double(a.pixels);
  std::cout << scene.name << " " << width << "x" << height << ": ids agree on " << 100.0 * share << "% ("
            << a.pixels - a.same << " differ: " << a.on_edge << " on an outline (" << a.shared
            << " of the pairs share a vertex), " << a.same_depth << " at the same depth, " << a.unexplained
            << " unexplained)\n";
  EXPECT_GE(share, 0.999);
  EXPECT_EQ(a.unexplained, 0u);
  return a;
}

// Where the triangle agrees, the receiver is Embree's up to the rounding of the hit distance.
void compare_receivers(const Scene& scene, const Camera& camera, int width, int height) {
  auto embree = EmbreeScene::build(scene);
  ASSERT_TRUE(embree);
  const PixelReceivers ours = raster_pixel_receivers(scene, camera, width, height);
  const PixelReceivers theirs = pixel_receivers(*embree, scene, camera, width, height);
  std::vector<std::int64_t> slot(static_cast<std::size_t>(width * height), -1);
  for (std::size_t i = 0; i < theirs.pixel.size(); ++i) slot[theirs.pixel[i]] = static_cast<std::int64_t>(i);
  std::size_t compared = 0;
  for (std::size_t i = 0; i < ours.pixel.size(); ++i) {
    ASSERT_TRUE(i == 0 || ours.pixel[i] > ours.pixel[i - 1]);  // pixel order
    EXPECT_EQ(ours.receivers[i].key, ours.pixel[i]);
    const std::int64_t j = slot[ours.pixel[i]];
    if (j < 0 || theirs.triangle[static_cast<std::size_t>(j)] != ours.triangle[i]) continue;
    const Receiver& a = ours.receivers[i];
    const Receiver& b = theirs.receivers[static_cast<std::size_t>(j)];
    EXPECT_EQ(a.normal, b.normal);
    EXPECT_EQ(a.key, b.key);
    const float distance = glm::length(b.position - camera.eye);
    EXPECT_LE(glm::length(a.position - b.position), 1e-5f * distance + 1e-6f * glm::length(camera.eye));
    ++compared;
  }
  EXPECT_GE(compared, theirs.pixel.size() * 99 / 100);
}

TEST(RasterGBuffer, MatchesEmbreeInsideRoom) {
  const Scene scene = make_room();
  compare_with_embree(scene, scene.cameras.at(0), 320, 240);
  compare_receivers(scene, scene.cameras.at(0), 160, 120);
}

// A camera a hair from the box's corner: big triangles cross the near plane and the guard band.
TEST(RasterGBuffer, MatchesEmbreeNearGeometry) {
  const Scene scene = make_room();
  const Camera camera = look_at({-0.38f, 0.98f, -0.38f}, {-3.0f, 0.0f, 2.0f}, 100.0f);
  compare_with_embree(scene, camera, 200, 150);
  const Camera floor = look_at({1.0f, 0.01f, 2.0f}, {-4.0f, 1.0f, -3.0f}, 90.0f);
  compare_with_embree(scene, floor, 200, 150);
}

TEST(RasterGBuffer, MatchesEmbreeOnConference) {
  const auto path = test::real_scene("Conference/conference.obj");
  EXAO_REQUIRE_SCENE(path);
  auto scene = load_polygon_soup(path.string());
  ASSERT_TRUE(scene) << scene.error().message;
  const Camera camera = look_at({-900.0f, 350.0f, -950.0f}, {600.0f, 150.0f, 300.0f}, 70.0f);
  compare_with_embree(*scene, camera, 512, 384);
  compare_receivers(*scene, camera, 160, 120);
}

TEST(RasterGBuffer, EmptyViewHasNoReceivers) {
  const Scene scene = make_room();
  // Looking away from a room seen from outside: nothing on screen.
  const Camera camera = look_at({0.0f, 2.0f, 40.0f}, {0.0f, 2.0f, 80.0f}, 60.0f);
  const PixelReceivers pixels = raster_pixel_receivers(scene, camera, 32, 24);
  EXPECT_TRUE(pixels.receivers.empty());
  EXPECT_EQ(pixels.width, 32);
  EXPECT_EQ(pixels.height, 24);
}

}  // namespace
}  // namespace exao::raster
