#pragma once
// exao::raster::PolygonRaster: which pixel centres a screen polygon covers, row by row.
//
// Coverage is decided by exact 64-bit edge functions on the subpixel grid (raster/projection.h):
// a pixel centre is covered iff it is strictly inside every edge of a convex part, or on an edge
// that is a top or left edge (the top-left fill rule of Direct3D and OpenGL). Each edge's
// function is evaluated from its lexicographically smaller end point, so two parts sharing an
// edge compute exactly opposite values there, and a centre on a shared edge belongs to exactly
// one of them (watertight).
//
// Snapping can make a convex polygon slightly non-convex (a near-zero edge whose snapped
// direction is arbitrary); its half-plane would then cut a whole strip off the polygon. So a
// polygon is drawn as one convex part only when its snapped vertices are exactly convex (all
// turns one way, winding once), and otherwise as a fan of triangles from its first vertex: each
// triangle is convex, the fan's inner edges are shared, and what snapping folds is confined to
// subpixel slivers.
//
// The covered centres of a convex part on a row form one span; its ends are estimated in double
// and then settled by the exact test.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

#include "raster/screen_polygon.h"

namespace exao::raster {

class PolygonRaster {
 public:
  static constexpr int kMaxParts = ScreenPolygon::kMaxVertices - 2;

  /// Sets up `polygon`; false when it is empty or has zero area.
  bool setup(const ScreenPolygon& polygon) {
    parts_ = 0;
    edges_ = 0;
    if (polygon.empty()) return false;
    x0_ = polygon.x0;
    x1_ = polygon.x1;
    y0_ = polygon.y0;
    y1_ = polygon.y1;
    const ScreenVertex* v = polygon.vertex.data();
    if (convex(v, polygon.count)) {
      add_part(v, polygon.count);
    } else {
      for (int i = 1; i + 1 < polygon.count; ++i) {
        const ScreenVertex triangle[3] = {v[0], v[i], v[i + 1]};
        add_part(triangle, 3);
      }
    }
    return parts_ > 0;
  }

  /// Pixels whose centres may be covered (inclusive, within the image).
  [[nodiscard]] int x0() const { return x0_; }
  [[nodiscard]] int x1() const { return x1_; }
  [[nodiscard]] int y0() const { return y0_; }
  [[nodiscard]] int y1() const { return y1_; }
  [[nodiscard]] int parts() const { return parts_; }

  /// Calls emit(xa, xb) for each span of covered pixel centres of row y within [lo, hi]. Spans
  /// of different parts are disjoint, but for subpixel slivers that snapping folded over.
  template <class Emit>
  void spans(int y, int lo, int hi, Emit&& emit) const {
    if (y < y0_ || y > y1_) return;
    for (int p = 0; p < parts_; ++p) {
      int xa = 0, xb = 0;
      if (span(part_[static_cast<std::size_t>(p)], y, lo, hi, xa, xb)) emit(xa, xb);
    }
  }

  /// Whether the centre of pixel (x, y) is covered (the same exact test as spans).
  [[nodiscard]] bool covers(int x, int y) const {
    bool covered = false;
    spans(y, x, x, [&](int, int) { covered = true; });
    return covered;
  }

 private:
  struct Edge {
    std::int64_t sx, sy, dx, dy, bias;
    double inverse_alpha;  // 1 / alpha (alpha = -dy * kSubpixel, the step per pixel), 0 if dy = 0
  };
  struct Part {
    int first_edge, edge_count;
    int x0, y0, x1, y1;  // pixel centres the part may cover
  };

  // Exactly convex: every turn the same way (or straight), and the edge directions' y
  // components change sign at most twice around the loop (so it winds once).
  static bool convex(const ScreenVertex* v, int n) {
    int turn = 0, changes = 0, first = 0, last = 0;
    for (int i = 0; i < n; ++i) {
      const ScreenVertex& a = v[i];
      const ScreenVertex& b = v[(i + 1) % n];
      const ScreenVertex& c = v[(i + 2) % n];
      const std::int64_t cross = (b.x - a.x) * (c.y - b.y) - (b.y - a.y) * (c.x - b.x);
      const int sign = (cross > 0) - (cross < 0);
      if (sign != 0) {
        if (turn != 0 && sign != turn) return false;
        turn = sign;
      }
      const int dy = (b.y > a.y) - (b.y < a.y);
      if (dy != 0) {
        if (first == 0) first = dy;
        if (last != 0 && dy != last) ++changes;
        last = dy;
      }
    }
    if (first != 0 && last != first) ++changes;
    return changes <= 2;
  }

  void add_part(const ScreenVertex* v, int n) {
    std::int64_t area2 = 0;  // twice the signed area; |coordinates| < 2^27, so no overflow
    std::int64_t lo_x = v[0].x, hi_x = v[0].x, lo_y = v[0].y, hi_y = v[0].y;
    for (int i = 0; i < n; ++i) {
      const ScreenVertex& a = v[i];
      const ScreenVertex& b = v[(i + 1) % n];
      area2 += a.x * b.y - b.x * a.y;
      lo_x = std::min(lo_x, a.x);
      hi_x = std::max(hi_x, a.x);
      lo_y = std::min(lo_y, a.y);
      hi_y = std::max(hi_y, a.y);
    }
    if (area2 == 0) return;
    Part& part = part_[static_cast<std::size_t>(parts_)];
    part.x0 = static_cast<int>(std::max<std::int64_t>(first_pixel_centre(lo_x), x0_));
    part.x1 = static_cast<int>(std::min<std::int64_t>(last_pixel_centre(hi_x), x1_));
    part.y0 = static_cast<int>(std::max<std::int64_t>(first_pixel_centre(lo_y), y0_));
    part.y1 = static_cast<int>(std::min<std::int64_t>(last_pixel_centre(hi_y), y1_));
    if (part.x0 > part.x1 || part.y0 > part.y1) return;
    ++parts_;
    part.first_edge = edges_;
    part.edge_count = n;
    const std::int64_t orientation = area2 > 0 ? 1 : -1;  // interior: every edge function > 0
    for (int i = 0; i < n; ++i) {
      const ScreenVertex& a = v[i];
      const ScreenVertex& b = v[(i + 1) % n];
      const bool a_first = a.x < b.x || (a.x == b.x && a.y < b.y);
      const ScreenVertex& s = a_first ? a : b;
      const ScreenVertex& e = a_first ? b : a;
      const std::int64_t sign = a_first ? orientation : -orientation;
      Edge& edge = edge_[static_cast<std::size_t>(edges_++)];
      edge.sx = s.x;
      edge.sy = s.y;
      edge.dx = sign * (e.x - s.x);
      edge.dy = sign * (e.y - s.y);
      // Screen y grows downwards: a left edge runs up (dy < 0), a top edge runs right.
      edge.bias = (edge.dy < 0 || (edge.dy == 0 && edge.dx > 0)) ? 1 : 0;
      edge.inverse_alpha = edge.dy == 0 ? 0.0 : 1.0 / static_cast<double>(-edge.dy * kSubpixel);
    }
  }

  // The covered pixel centres of row y within [lo, hi] of one part: [xa, xb], or false.
  bool span(const Part& part, int y, int lo, int hi, int& xa, int& xb) const {
    if (y < part.y0 || y > part.y1) return false;
    lo = std::max(lo, part.x0);
    hi = std::min(hi, part.x1);
    if (lo > hi) return false;
    const std::int64_t yp = kSubpixel * y + kSubpixel / 2;
    for (int i = part.first_edge; i < part.first_edge + part.edge_count; ++i) {
      const Edge& e = edge_[static_cast<std::size_t>(i)];
      // E(x) = dx (Y - sy) - dy (X - sx) at X = S x + S/2, written alpha x + beta (+ bias > 0).
      const std::int64_t alpha = -e.dy * kSubpixel;
      const std::int64_t beta = e.dx * (yp - e.sy) - e.dy * (kSubpixel / 2 - e.sx) + e.bias;
      const auto covered = [&](std::int64_t x) { return alpha * x + beta > 0; };
      if (alpha == 0) {
        if (beta <= 0) return false;
        continue;
      }
      // The double estimate is within far less than a pixel (|beta| < 2^58); the loops settle it.
      const double bound = -static_cast<double>(beta) * e.inverse_alpha;
      if (alpha > 0) {  // covered for x > bound: raise lo
        auto x = static_cast<std::int64_t>(std::clamp(std::floor(bound) + 1.0, double(lo), double(hi) + 1.0));
        while (x <= hi && !covered(x)) ++x;
        while (x > lo && covered(x - 1)) --x;
        lo = static_cast<int>(x);
      } else {  // covered for x < bound: lower hi
        auto x = static_cast<std::int64_t>(std::clamp(std::ceil(bound) - 1.0, double(lo) - 1.0, double(hi)));
        while (x >= lo && !covered(x)) --x;
        while (x < hi && covered(x + 1)) ++x;
        hi = static_cast<int>(x);
      }
      if (lo > hi) return false;
    }
    xa = lo;
    xb = hi;
    return true;
  }

  std::array<Edge, 3 * kMaxParts> edge_;
  std::array<Part, kMaxParts> part_;
  int edges_ = 0, parts_ = 0;
  int x0_ = 0, x1_ = -1, y0_ = 0, y1_ = -1;
};

}  // namespace exao::raster
