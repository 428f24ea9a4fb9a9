#include "raster/screen_polygon.h"

#include <algorithm>
#include <cmath>

#include "core/check.h"

namespace exao::raster {
namespace {

bool lexicographic_less(const ClipVertex& a, const ClipVertex& b) {
  if (a.x != b.x) return a.x < b.x;
  if (a.y != b.y) return a.y < b.y;
  return a.w < b.w;
}

// The point where edge (a, b) crosses clip plane `plane`, computed from the lexicographically
// smaller end point, so that (a, b) and (b, a) give the same bits.
ClipVertex crossing(const Projection& projection, const ClipVertex& a, const ClipVertex& b, int plane) {
  const bool forward = lexicographic_less(a, b);
  const ClipVertex& s = forward ? a : b;
  const ClipVertex& e = forward ? b : a;
  const double ds = clip_distance(projection, s, plane);
  const double de = clip_distance(projection, e, plane);
  const double t = ds / (ds - de);
  return {s.x + t * (e.x - s.x), s.y + t * (e.y - s.y), s.w + t * (e.w - s.w)};
}

}  // namespace

ScreenVertex Projection::to_screen(const ClipVertex& c) const {
  const double px = screen_x(c.x / c.w) * static_cast<double>(kSubpixel);
  const double py = screen_y(c.y / c.w) * static_cast<double>(kSubpixel);
  return {std::llround(px), std::llround(py)};
}

Projection Projection::make(const Camera& camera, int width, int height, double near) {
  EXAO_CHECK_GE(width, 1);
  EXAO_CHECK_GE(height, 1);
  EXAO_CHECK_LE(width, kMaxImageSize);
  EXAO_CHECK_LE(height, kMaxImageSize);
  EXAO_CHECK_GT(near, 0.0);
  Projection p;
  // The same float quantities pixel_ray computes.
  const float tan_half = std::tan(0.5f * camera.yfov);
  const float aspect = static_cast<float>(width) / static_cast<float>(height);
  const glm::vec3 right = glm::cross(camera.forward, camera.up);
  p.eye = glm::dvec3(camera.eye);
  p.right = glm::dvec3(right);
  p.up = glm::dvec3(camera.up);
  p.forward = glm::dvec3(camera.forward);
  p.kx = 1.0 / (static_cast<double>(tan_half) * static_cast<double>(aspect));
  p.ky = 1.0 / static_cast<double>(tan_half);
  p.width = width;
  p.height = height;
  p.near = near;
  return p;
}

ScreenPolygon make_screen_polygon(const Projection& projection, std::span<const ClipVertex> clip) {
  EXAO_CHECK_GE(clip.size(), 3u);
  EXAO_CHECK_LE(clip.size(), ScreenPolygon::kMaxInput);
  ScreenPolygon out;

  // Which planes does anything cross? Most polygons are wholly inside and skip clipping.
  int outside_any = 0;
  for (int plane = 0; plane < kClipPlanes; ++plane) {
    int outside = 0;
    for (const ClipVertex& v : clip) outside += clip_distance(projection, v, plane) < 0.0;
    if (outside == static_cast<int>(clip.size())) return out;  // wholly outside one plane
    if (outside > 0) outside_any |= 1 << plane;
  }

  std::array<ClipVertex, ScreenPolygon::kMaxVertices> buffer[2];
  int count = static_cast<int>(clip.size());
  std::copy(clip.begin(), clip.end(), buffer[0].begin());
  int current = 0;
  for (int plane = 0; plane < kClipPlanes; ++plane) {
    if (!(outside_any >> plane & 1)) continue;
    const auto& in = buffer[current];
    auto& next = buffer[1 - current];
    int n = 0;
    for (int i = 0; i < count; ++i) {
      const ClipVertex& a = in[static_cast<std::size_t>(i)];
      const ClipVertex& b = in[static_cast<std::size_t>((i + 1) % count)];
      const bool a_in = clip_distance(projection, a, plane) >= 0.0;
      const bool b_in = clip_distance(projection, b, plane) >= 0.0;
      if (a_in) next[static_cast<std::size_t>(n++)] = a;
      if (a_in != b_in) next[static_cast<std::size_t>(n++)] = crossing(projection, a, b, plane);
    }
    count = n;
    current = 1 - current;
    if (count < 3) return out;
  }

  // Project, snap, and merge consecutive duplicates (a zero-length edge has no fill rule).
  int n = 0;
  for (int i = 0; i < count; ++i) {
    const ScreenVertex v = projection.to_screen(buffer[current][static_cast<std::size_t>(i)]);
    if (n > 0 && out.vertex[static_cast<std::size_t>(n - 1)] == v) continue;
    out.vertex[static_cast<std::size_t>(n++)] = v;
  }
  while (n > 1 && out.vertex[static_cast<std::size_t>(n - 1)] == out.vertex[0]) --n;
  if (n < 3) return out;
  out.count = n;

  // Pixel centres (x + 1/2) * kSubpixel inside the vertices' bounding box, clamped to the image.
  std::int64_t lo_x = out.vertex[0].x, hi_x = lo_x, lo_y = out.vertex[0].y, hi_y = lo_y;
  for (int i = 1; i < n; ++i) {
    lo_x = std::min(lo_x, out.vertex[static_cast<std::size_t>(i)].x);
    hi_x = std::max(hi_x, out.vertex[static_cast<std::size_t>(i)].x);
    lo_y = std::min(lo_y, out.vertex[static_cast<std::size_t>(i)].y);
    hi_y = std::max(hi_y, out.vertex[static_cast<std::size_t>(i)].y);
  }
  out.x0 = static_cast<int>(std::max<std::int64_t>(first_pixel_centre(lo_x), 0));
  out.x1 = static_cast<int>(std::min<std::int64_t>(last_pixel_centre(hi_x), projection.width - 1));
  out.y0 = static_cast<int>(std::max<std::int64_t>(first_pixel_centre(lo_y), 0));
  out.y1 = static_cast<int>(std::min<std::int64_t>(last_pixel_centre(hi_y), projection.height - 1));
  return out;
}

}  // namespace exao::raster
