#include "raster/influence_volume.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <numbers>
#include <span>

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
    assert(volume_.vertex_count < InfluenceVolume::kMaxVertices);
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
    assert(volume_.face_count < InfluenceVolume::kMaxFaces);
    auto& f = volume_.face[static_cast<std::size_t>(volume_.face_count++)];
    f.first = static_cast<std::uint8_t>(used_);
    f.count = static_cast<std::uint8_t>(vertices.size());
    f.depth = depth;
    for (const int v : vertices) {
      assert(used_ < InfluenceVolume::kMaxIndices);
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
  const glm::dvec3 v[3] = {glm::dvec3(triangles.v0[t]), glm::dvec3(triangles.v1[t]), glm::dvec3(triangles.v2[t])};
  const glm::dvec3 centre(triangles.centre[t]);
  const double R = triangles.radius[t];
  const double r = params.radius, grow = params.grow, G = params.slack;

  // --- The triangle's plane, and how well float arithmetic knows it. ---
  const glm::dvec3 n = glm::cross(v[1] - v[0], v[2] - v[0]);
  const double n_length = glm::length(n);
  const double longest = std::sqrt(std::max({glm::dot(v[1] - v[0], v[1] - v[0]), glm::dot(v[2] - v[1], v[2] - v[1]),
                                             glm::dot(v[0] - v[2], v[0] - v[2])}));
  bool degenerate = !(n_length > 1e-12 * longest * longest) || !std::isfinite(n_length);
  const glm::dvec3 unit = degenerate ? glm::dvec3(0.0) : n / n_length;
  // triangle_mask computes the plane from vertices in the receiver frame, each off by a few ulps
  // of its distance (< 2R + r) from the receiver: its normal is off by about
  // 4 ulp (2R + r) L / (2 area) radians (ulp = 2^-24, L the longest edge); theta is that with a
  // factor of about 80 to spare, and the plane-distance slack is theta times the reach.
  const double reach = 2.0 * R + grow;
  const double theta = degenerate ? kInfinity : 1e-5 * reach * longest / (0.5 * n_length);
  const double plane_slack = G + 2.0 * theta * reach;
  const double h = glm::dot(unit, v[0]);

  TriangleCull& cull = volume.cull;
  cull.v0 = triangles.v0[t];
  cull.v1 = triangles.v1[t];
  cull.v2 = triangles.v2[t];
  cull.centre = triangles.centre[t];
  cull.sphere_reach2 = static_cast<float>((R + r + G) * (R + r + G));
  cull.normal = glm::vec3(unit);
  cull.plane_slack = static_cast<float>(std::min(plane_slack, 1e30));
  cull.plane_reach = static_cast<float>(std::min(r + plane_slack, 1e30));
  cull.near_depth = static_cast<float>(std::min({projection.to_clip(v[0]).w, projection.to_clip(v[1]).w, projection.to_clip(v[2]).w}));
  cull.depth_reach = static_cast<float>(r + G);
  cull.slack = static_cast<float>(G);
  cull.one_sided = !triangles.two_sided[t];

  // One-sided: receivers with a non-empty mask have p' at signed distance > -plane_slack, so p
  // (eps from p') at > -(plane_slack + eps); the base goes a margin 3 G further.
  const double base = plane_slack + params.offset + 3.0 * G;
  const bool half_space = cull.one_sided && !degenerate && base < grow;

  // --- The prism's hexagon (paper Fig. 2), in the triangle's plane. ---
  glm::dvec3 hexagon[6], side[6];
  if (!degenerate) {
    glm::dvec3 edge_normal[3];  // outward in-plane normal of edge k (from v[k] to v[k+1])
    for (int k = 0; k < 3; ++k) edge_normal[k] = glm::normalize(glm::cross(v[(k + 1) % 3] - v[k], unit));
    for (int k = 0; k < 3; ++k) {
      const glm::dvec3& before = edge_normal[(k + 2) % 3];  // edge ending at v[k]
      const glm::dvec3& after = edge_normal[k];             // edge starting at v[k]
      const glm::dvec3 sum = before + after;
      const double sum_length = glm::length(sum);
      if (!(sum_length > 1e-6) || !std::isfinite(sum_length)) {
        degenerate = true;
        break;
      }
      const glm::dvec3 u = sum / sum_length;  // bisector: in the normal cone at v[k]
      hexagon[2 * k] = v[k] + grow * (before + u) / (1.0 + glm::dot(before, u));
      hexagon[2 * k + 1] = v[k] + grow * (after + u) / (1.0 + glm::dot(after, u));
      side[2 * k] = u;          // the cap from hexagon[2k] to hexagon[2k+1]
      side[2 * k + 1] = after;  // the edge line from hexagon[2k+1] to hexagon[2k+2]
    }
  }

  Shape shape(projection, params, volume);
  const double sphere = R + grow;
  const glm::dvec3 to_centre = centre - projection.eye;
  const double distance = glm::length(to_centre);
  const double centre_depth = glm::dot(to_centre, projection.forward);
  const bool billboard_fits = distance > 1.25 * sphere && centre_depth - sphere > 2.0 * projection.near;

  if ((R <= params.alpha * r || degenerate) && billboard_fits) {
    // --- Billboard (paper Fig. 3). ---
    volume.shape = VolumeShape::Billboard;
    const glm::dvec3 axis = to_centre / distance;
    const double ratio = sphere / distance;
    const glm::dvec3 circle_centre = projection.eye + axis * (distance - sphere * ratio);
    const double circle_radius = sphere * std::sqrt(1.0 - ratio * ratio);
    glm::dvec3 silhouette[kBillboardSides + 1], cap[kBillboardSides + 1], disc[kBillboardSides];
    int cap_count = circumscribed_polygon(circle_centre, axis, circle_radius, silhouette);
    std::copy(silhouette, silhouette + cap_count, cap);
    int disc_count = 0;
    if (half_space && !degenerate) {
      const double base_plane = h - base;  // in front: dot(unit, x) >= base_plane
      const double height = glm::dot(unit, centre) - base_plane;
      if (height <= -sphere) return false;  // the sphere is wholly behind: nothing to occlude
      if (height < sphere) {
        cap_count = clip_polygon(silhouette, cap_count, unit, base_plane, cap);
        disc_count = circumscribed_polygon(centre - height * unit, unit, std::sqrt(sphere * sphere - height * height), disc);
      }
    }
    const DepthPlane depth{glm::vec3(projection.forward), static_cast<float>(centre_depth + sphere)};
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
    volume.max_depth = centre_depth + sphere;
    return volume.face_count > 0;
  }

  if (!degenerate) {
    // --- Prism: 12 vertices, faces top, bottom and six sides, each a support plane. ---
    volume.shape = VolumeShape::Prism;
    const double below = half_space ? base : grow;
    int top[6], bottom[6];
    for (int k = 0; k < 6; ++k) {
      top[k] = shape.vertex(hexagon[k] + grow * unit);
      bottom[k] = shape.vertex(hexagon[k] - below * unit);
    }
    shape.polyhedron_face(top, unit, h + grow);
    const int bottom_reversed[6] = {bottom[5], bottom[4], bottom[3], bottom[2], bottom[1], bottom[0]};
    shape.polyhedron_face(bottom_reversed, -unit, -(h - below));
    for (int k = 0; k < 6; ++k) {
      const int j = (k + 1) % 6;
      const int quad[4] = {bottom[k], bottom[j], top[j], top[k]};
      shape.polyhedron_face(quad, side[k], glm::dot(side[k], hexagon[k]));
    }
    return volume.face_count > 0;
  }

  // --- Box around the influence sphere. ---
  volume.shape = VolumeShape::Box;
  int corner[8];
  for (int i = 0; i < 8; ++i) {
    corner[i] = shape.vertex(centre + sphere * glm::dvec3(i & 1 ? 1.0 : -1.0, i & 2 ? 1.0 : -1.0, i & 4 ? 1.0 : -1.0));
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
      shape.polyhedron_face(quad, m, sign * centre[axis] + sphere);
    }
  }
  return volume.face_count > 0;
}

}  // namespace exao::raster
