#include "raster/influence_volume.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <span>

#include "core/check.h"

namespace exao::raster {
namespace {

constexpr int kBillboardSides = 12;  // the paper's polygons: 12 vertices each
constexpr double kInfinity = std::numeric_limits<double>::infinity();

// Builder of a volume: world vertices into clip space, faces as index lists.
class Shape {
 public:
  Shape(const Projection& projection, const VolumeParams& params, InfluenceVolume& volume)
      : projection_(projection), params_(params), volume_(volume) {
    volume_.vertex_count = 0;
    volume_.face_count = 0;
    volume_.exclude_first = false;
    volume_.max_depth = -kInfinity;
  }

  int vertex(const glm::dvec3& p) {
    EXAO_CHECK_LT(volume_.vertex_count, InfluenceVolume::kMaxVertices);
    const ClipVertex c = projection_.to_clip(p);
    volume_.max_depth = std::max(volume_.max_depth, c.w);
    volume_.clip[static_cast<std::size_t>(volume_.vertex_count)] = c;
    return volume_.vertex_count++;
  }

  // A face of a convex polyhedron, its outward plane dot(m, x) <= h (world): kept when it is a
  // far face, i.e. the eye is on the inner side (or, within the slack, on the plane).
  void polyhedron_face(std::span<const int> vertices, const glm::dvec3& m, double h) {
    const double h_eye = h - glm::dot(m, projection_.eye);
    if (h_eye < -double(params_.slack)) return;
    face(vertices, DepthPlane{glm::vec3(m), static_cast<float>(h_eye)});
  }

  void face(std::span<const int> vertices, const DepthPlane& depth) {
    EXAO_CHECK_LT(volume_.face_count, InfluenceVolume::kMaxFaces);
    auto& f = volume_.face[static_cast<std::size_t>(volume_.face_count++)];
    f.first = static_cast<std::uint8_t>(used_);
    f.count = static_cast<std::uint8_t>(vertices.size());
    f.depth = depth;
    for (const int v : vertices) {
      EXAO_CHECK_LT(used_, InfluenceVolume::kMaxIndices);
      volume_.index[static_cast<std::size_t>(used_++)] = static_cast<std::uint8_t>(v);
    }
  }

 private:
  const Projection& projection_;
  const VolumeParams& params_;
  InfluenceVolume& volume_;
  int used_ = 0;
};

// Two unit vectors completing unit `a` to an orthonormal basis.
void basis(const glm::dvec3& a, glm::dvec3& e1, glm::dvec3& e2) {
  const glm::dvec3 helper = std::abs(a.x) < 0.6 ? glm::dvec3(1.0, 0.0, 0.0) : glm::dvec3(0.0, 1.0, 0.0);
  e1 = glm::normalize(glm::cross(a, helper));
  e2 = glm::cross(a, e1);
}

// A regular polygon circumscribing the circle (centre, radius) of the plane with unit normal
// `axis`: vertices at radius / cos(pi / k), so the edges touch the circle.
int circumscribed_polygon(const glm::dvec3& centre, const glm::dvec3& axis, double radius, glm::dvec3* out) {
  static const auto directions = [] {  // (cos, sin) of 2 pi j / k, and 1 / cos(pi / k)
    std::array<glm::dvec2, kBillboardSides + 1> d;
    for (int j = 0; j < kBillboardSides; ++j) {
      const double angle = 2.0 * std::numbers::pi * j / kBillboardSides;
      d[static_cast<std::size_t>(j)] = {std::cos(angle), std::sin(angle)};
    }
    d[kBillboardSides] = {1.0 / std::cos(std::numbers::pi / kBillboardSides), 0.0};
    return d;
  }();
  glm::dvec3 e1, e2;
  basis(axis, e1, e2);
  const double reach = radius * directions[kBillboardSides].x;
  for (int j = 0; j < kBillboardSides; ++j) {
    const glm::dvec2& d = directions[static_cast<std::size_t>(j)];
    out[j] = centre + reach * (d.x * e1 + d.y * e2);
  }
  return kBillboardSides;
}

// Sutherland-Hodgman against the half-space dot(m, x) >= h.
int clip_polygon(const glm::dvec3* in, int count, const glm::dvec3& m, double h, glm::dvec3* out) {
  int n = 0;
  for (int i = 0; i < count; ++i) {
    const glm::dvec3& a = in[i];
    const glm::dvec3& b = in[(i + 1) % count];
    const double da = glm::dot(m, a) - h, db = glm::dot(m, b) - h;
    if (da >= 0.0) out[n++] = a;
    if ((da >= 0.0) != (db >= 0.0)) out[n++] = a + (da / (da - db)) * (b - a);
  }
  return n;
}

// Step 1: the triangle's plane, and how well float arithmetic knows it.
struct TrianglePlane {
  glm::dvec3 v[3];
  glm::dvec3 unit{0.0};  // the unit normal; zero when degenerate
  double h = 0.0;        // dot(unit, v0)
  double plane_slack = 0.0;
  double base = 0.0;     // how far below the plane a one-sided triangle's volume reaches
  bool degenerate = false;
};

TrianglePlane triangle_plane(const lut::TriangleSet& triangles, std::uint32_t t, const VolumeParams& params) {
  TrianglePlane plane;
  const glm::dvec3* v = plane.v;
  plane.v[0] = glm::dvec3(triangles.v0[t]);
  plane.v[1] = glm::dvec3(triangles.v1[t]);
  plane.v[2] = glm::dvec3(triangles.v2[t]);
  const double R = triangles.radius[t];
  const double grow = params.grow, G = params.slack;
  const glm::dvec3 n = glm::cross(v[1] - v[0], v[2] - v[0]);
  const double n_length = glm::length(n);
  const double longest = std::sqrt(std::max({glm::dot(v[1] - v[0], v[1] - v[0]), glm::dot(v[2] - v[1], v[2] - v[1]),
                                             glm::dot(v[0] - v[2], v[0] - v[2])}));
  plane.degenerate = !(n_length > 1e-12 * longest * longest) || !std::isfinite(n_length);
  plane.unit = plane.degenerate ? glm::dvec3(0.0) : n / n_length;
  // triangle_mask computes the plane from vertices in the receiver frame, each off by a few ulps
  // of its distance (< 2R + r) from the receiver: its normal is off by about
  // 4 ulp (2R + r) L / (2 area) radians (ulp = 2^-24, L the longest edge); theta is that with a
  // factor of about 80 to spare, and the plane-distance slack is theta times the reach.
  const double reach = 2.0 * R + grow;
  const double theta = plane.degenerate ? kInfinity : 1e-5 * reach * longest / (0.5 * n_length);
  plane.plane_slack = G + 2.0 * theta * reach;
  plane.h = glm::dot(plane.unit, v[0]);
  // One-sided: receivers with a non-empty mask have p' at signed distance > -plane_slack, so p
  // (eps from p') at > -(plane_slack + eps); the base goes a margin 3 G further.
  plane.base = plane.plane_slack + params.offset + 3.0 * G;
  return plane;
}

// Step 2: what the five fragment tests need of the triangle.
void fill_cull(const lut::TriangleSet& triangles, std::uint32_t t, const TrianglePlane& plane, const VolumeParams& params,
               const Projection& projection, TriangleCull& cull) {
  const double R = triangles.radius[t];
  const double r = params.radius, G = params.slack;
  cull.v0 = triangles.v0[t];
  cull.v1 = triangles.v1[t];
  cull.v2 = triangles.v2[t];
  cull.centre = triangles.centre[t];
  cull.sphere_reach2 = static_cast<float>((R + r + G) * (R + r + G));
  cull.normal = glm::vec3(plane.unit);
  cull.plane_slack = static_cast<float>(std::min(plane.plane_slack, 1e30));
  cull.plane_reach = static_cast<float>(std::min(r + plane.plane_slack, 1e30));
  cull.near_depth = static_cast<float>(
      std::min({projection.to_clip(plane.v[0]).w, projection.to_clip(plane.v[1]).w, projection.to_clip(plane.v[2]).w}));
  cull.depth_reach = static_cast<float>(r + G);
  cull.slack = static_cast<float>(G);
  cull.one_sided = !triangles.two_sided[t];
}

// Step 3: the prism's hexagon (paper Fig. 2), in the triangle's plane: its corners, and the
// outward normal of each side. False when the triangle is too thin to have one.
struct Hexagon {
  glm::dvec3 corner[6];
  glm::dvec3 side[6];  // side k runs from corner k to corner k + 1
};

bool prism_hexagon(const TrianglePlane& plane, double grow, Hexagon& out) {
  const glm::dvec3* v = plane.v;
  glm::dvec3 edge_normal[3];  // outward in-plane normal of edge k (from v[k] to v[k+1])
  for (int k = 0; k < 3; ++k) edge_normal[k] = glm::normalize(glm::cross(v[(k + 1) % 3] - v[k], plane.unit));
  for (int k = 0; k < 3; ++k) {
    const glm::dvec3& before = edge_normal[(k + 2) % 3];  // edge ending at v[k]
    const glm::dvec3& after = edge_normal[k];             // edge starting at v[k]
    const glm::dvec3 sum = before + after;
    const double sum_length = glm::length(sum);
    if (!(sum_length > 1e-6) || !std::isfinite(sum_length)) return false;
    const glm::dvec3 u = sum / sum_length;  // bisector: in the normal cone at v[k]
    out.corner[2 * k] = v[k] + grow * (before + u) / (1.0 + glm::dot(before, u));
    out.corner[2 * k + 1] = v[k] + grow * (after + u) / (1.0 + glm::dot(after, u));
    out.side[2 * k] = u;          // the cap from corner 2k to corner 2k+1
    out.side[2 * k + 1] = after;  // the edge line from corner 2k+1 to corner 2k+2
  }
  return true;
}

// Step 4: the influence sphere as the eye sees it, and whether a billboard can stand for it.
struct Sphere {
  double R = 0.0;       // the triangle's bounding sphere
  glm::dvec3 centre{0.0};
  double radius = 0.0;  // R + grow: the sphere of influence
  glm::dvec3 to_centre{0.0};
  double distance = 0.0;
  double centre_depth = 0.0;
  bool billboard_fits = false;
};

Sphere influence_sphere(const lut::TriangleSet& triangles, std::uint32_t t, const VolumeParams& params,
                        const Projection& projection) {
  Sphere s;
  s.R = triangles.radius[t];
  s.centre = glm::dvec3(triangles.centre[t]);
  s.radius = s.R + params.grow;
  s.to_centre = s.centre - projection.eye;
  s.distance = glm::length(s.to_centre);
  s.centre_depth = glm::dot(s.to_centre, projection.forward);
  s.billboard_fits = s.distance > 1.25 * s.radius && s.centre_depth - s.radius > 2.0 * projection.near;
  return s;
}

// Step 5a: the billboard (paper Fig. 3): the sphere's silhouette, cut by the base plane of a
// one-sided triangle.
bool billboard(const TrianglePlane& plane, const Sphere& sphere, bool half_space, const Projection& projection,
               Shape& shape, InfluenceVolume& volume) {
  volume.shape = VolumeShape::Billboard;
  const glm::dvec3 axis = sphere.to_centre / sphere.distance;
  const double ratio = sphere.radius / sphere.distance;
  const glm::dvec3 circle_centre = projection.eye + axis * (sphere.distance - sphere.radius * ratio);
  const double circle_radius = sphere.radius * std::sqrt(1.0 - ratio * ratio);
  glm::dvec3 silhouette[kBillboardSides + 1], cap[kBillboardSides + 1], disc[kBillboardSides];
  int cap_count = circumscribed_polygon(circle_centre, axis, circle_radius, silhouette);
  std::copy(silhouette, silhouette + cap_count, cap);
  int disc_count = 0;
  if (half_space && !plane.degenerate) {
    const double base_plane = plane.h - plane.base;  // in front: dot(unit, x) >= base_plane
    const double height = glm::dot(plane.unit, sphere.centre) - base_plane;
    if (height <= -sphere.radius) return false;  // the sphere is wholly behind: nothing to occlude
    if (height < sphere.radius) {
      cap_count = clip_polygon(silhouette, cap_count, plane.unit, base_plane, cap);
      disc_count = circumscribed_polygon(sphere.centre - height * plane.unit, plane.unit,
                                         std::sqrt(sphere.radius * sphere.radius - height * height), disc);
    }
  }
  const DepthPlane depth{glm::vec3(projection.forward), static_cast<float>(sphere.centre_depth + sphere.radius)};
  int ids[kBillboardSides + 1];
  if (cap_count >= 3) {
    for (int i = 0; i < cap_count; ++i) ids[i] = shape.vertex(cap[i]);
    shape.face({ids, static_cast<std::size_t>(cap_count)}, depth);
  }
  if (disc_count >= 3) {
    volume.exclude_first = cap_count >= 3;
    for (int i = 0; i < disc_count; ++i) ids[i] = shape.vertex(disc[i]);
    shape.face({ids, static_cast<std::size_t>(disc_count)}, depth);
  }
  volume.max_depth = sphere.centre_depth + sphere.radius;
  return volume.face_count > 0;
}

// Step 5b: the prism: 12 vertices, faces top, bottom and six sides, each a support plane.
bool prism(const TrianglePlane& plane, const Hexagon& hexagon, bool half_space, double grow, Shape& shape,
           InfluenceVolume& volume) {
  volume.shape = VolumeShape::Prism;
  const double below = half_space ? plane.base : grow;
  int top[6], bottom[6];
  for (int k = 0; k < 6; ++k) {
    top[k] = shape.vertex(hexagon.corner[k] + grow * plane.unit);
    bottom[k] = shape.vertex(hexagon.corner[k] - below * plane.unit);
  }
  shape.polyhedron_face(top, plane.unit, plane.h + grow);
  const int bottom_reversed[6] = {bottom[5], bottom[4], bottom[3], bottom[2], bottom[1], bottom[0]};
  shape.polyhedron_face(bottom_reversed, -plane.unit, -(plane.h - below));
  for (int k = 0; k < 6; ++k) {
    const int j = (k + 1) % 6;
    const int quad[4] = {bottom[k], bottom[j], top[j], top[k]};
    shape.polyhedron_face(quad, hexagon.side[k], glm::dot(hexagon.side[k], hexagon.corner[k]));
  }
  return volume.face_count > 0;
}

// Step 5c: a box around the influence sphere, for a degenerate triangle too close for a billboard.
bool box(const Sphere& sphere, Shape& shape, InfluenceVolume& volume) {
  volume.shape = VolumeShape::Box;
  int corner[8];
  for (int i = 0; i < 8; ++i) {
    corner[i] = shape.vertex(sphere.centre +
                             sphere.radius * glm::dvec3(i & 1 ? 1.0 : -1.0, i & 2 ? 1.0 : -1.0, i & 4 ? 1.0 : -1.0));
  }
  for (int axis = 0; axis < 3; ++axis) {
    const int bit = 1 << axis;
    for (const double sign : {-1.0, 1.0}) {
      int quad[4], q = 0;
      for (int i = 0; i < 8; ++i) {
        if (((i & bit) != 0) == (sign > 0.0)) quad[q++] = corner[i];
      }
      std::swap(quad[2], quad[3]);  // corners in cyclic order around the face
      glm::dvec3 m(0.0);
      m[axis] = sign;
      shape.polyhedron_face(quad, m, sign * sphere.centre[axis] + sphere.radius);
    }
  }
  return volume.face_count > 0;
}

}  // namespace

VolumeParams make_volume_params(const ShadowRays& rays, double scene_scale, float alpha, double near) {
  VolumeParams p;
  p.radius = rays.radius;
  p.offset = rays.origin_offset;
  p.slack = static_cast<float>(2e-5 * (scene_scale + double(rays.radius)));
  p.grow = rays.radius + rays.origin_offset + 4.0f * p.slack;
  p.alpha = alpha;
  p.near = near;
  return p;
}

bool build_volume(const lut::TriangleSet& triangles, std::uint32_t t, const VolumeParams& params,
                  const Projection& projection, InfluenceVolume& volume) {
  TrianglePlane plane = triangle_plane(triangles, t, params);
  fill_cull(triangles, t, plane, params, projection, volume.cull);
  const bool half_space = volume.cull.one_sided && !plane.degenerate && plane.base < params.grow;
  Hexagon hexagon;
  if (!plane.degenerate && !prism_hexagon(plane, params.grow, hexagon)) plane.degenerate = true;

  Shape shape(projection, params, volume);
  const Sphere sphere = influence_sphere(triangles, t, params, projection);
  if ((sphere.R <= params.alpha * static_cast<double>(params.radius) || plane.degenerate) && sphere.billboard_fits) {
    return billboard(plane, sphere, half_space, projection, shape, volume);
  }
  if (!plane.degenerate) return prism(plane, hexagon, half_space, params.grow, shape, volume);
  return box(sphere, shape, volume);
}

}  // namespace exao::raster
