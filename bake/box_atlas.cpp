#include "bake/box_atlas.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>
#include <unordered_map>

#include "core/position_key.h"

namespace exao::bake {
namespace {

// 0..5: +X, -X, +Y, -Y, +Z, -Z, the axis the normal is closest to.
int dominant_axis(const glm::vec3& n) {
  const glm::vec3 a = glm::abs(n);
  const int k = a.x >= a.y && a.x >= a.z ? 0 : (a.y >= a.z ? 1 : 2);
  return 2 * k + (n[k] < 0.0f ? 1 : 0);
}

struct Chart {
  std::vector<std::uint32_t> triangles;
  int axis = 0;
  glm::vec2 lo{0.0f}, hi{0.0f};  // projected bounds, world units
  glm::vec2 origin{0.0f};        // where its padded footprint starts, uv units
};

glm::vec2 project(const glm::vec3& p, int axis) {
  switch (axis / 2) {
    case 0: return {p.z, p.y};
    case 1: return {p.x, p.z};
    default: return {p.x, p.y};
  }
}

using Flat = std::array<glm::dvec2, 3>;

// Whether two projected triangles share interior points: by the separating axis theorem, two
// convex polygons with disjoint interiors are separated along the normal of one of their edges.
// Touching (a shared edge or corner) is not overlap; `eps` absorbs rounding of shared vertices.
bool interiors_overlap(const Flat& a, const Flat& b, double eps) {
  for (const Flat* t : {&a, &b}) {
    for (int e = 0; e < 3; ++e) {
      const glm::dvec2 d = (*t)[static_cast<std::size_t>((e + 1) % 3)] - (*t)[static_cast<std::size_t>(e)];
      const glm::dvec2 n(-d.y, d.x);
      double lo_a = std::numeric_limits<double>::infinity(), hi_a = -lo_a, lo_b = lo_a, hi_b = -lo_a;
      for (int k = 0; k < 3; ++k) {
        const double pa = glm::dot(n, a[static_cast<std::size_t>(k)]), pb = glm::dot(n, b[static_cast<std::size_t>(k)]);
        lo_a = std::min(lo_a, pa);
        hi_a = std::max(hi_a, pa);
        lo_b = std::min(lo_b, pb);
        hi_b = std::max(hi_b, pb);
      }
      const double tolerance = eps * glm::length(n);
      if (hi_a <= lo_b + tolerance || hi_b <= lo_a + tolerance) return false;
    }
  }
  return true;
}

// The projected triangles of one chart on a uniform grid, so that a candidate is tested only
// against the triangles near it.
class ChartGrid {
 public:
  explicit ChartGrid(double cell) : cell_(cell) {}
  void clear() {
    cells_.clear();
    big_.clear();
    all_.clear();
  }
  [[nodiscard]] bool overlaps(const Flat& t, std::span<const Flat> flats, double eps) const {
    // A big candidate is tested against everything; others against the big ones and their cells.
    for (const std::uint32_t other : span(t) > kMaxSpan ? all_ : big_) {
      if (interiors_overlap(t, flats[other], eps)) return true;
    }
    if (span(t) > kMaxSpan) return false;
    bool hit = false;
    visit(t, [&](const std::vector<std::uint32_t>* cell) {
      if (cell == nullptr || hit) return;
      for (const std::uint32_t other : *cell) {
        if (interiors_overlap(t, flats[other], eps)) {
          hit = true;
          return;
        }
      }
    });
    return hit;
  }
  void add(const Flat& t, std::uint32_t id) {
    all_.push_back(id);
    if (span(t) > kMaxSpan) {
      big_.push_back(id);  // tested against every candidate rather than listed in many cells
      return;
    }
    visit_keys(t, [&](std::uint64_t key) { cells_[key].push_back(id); });
  }

 private:
  static constexpr std::int64_t kMaxSpan = 64;  // cells per side a listed triangle may cover
  // Cells a triangle's bounding box covers along its longer side.
  [[nodiscard]] std::int64_t span(const Flat& t) const {
    const glm::dvec2 lo = glm::min(glm::min(t[0], t[1]), t[2]), hi = glm::max(glm::max(t[0], t[1]), t[2]);
    return static_cast<std::int64_t>(std::max(hi.x - lo.x, hi.y - lo.y) / cell_) + 1;
  }
  // Calls f for every cell the triangle's bounding box covers (only for triangles of at most
  // kMaxSpan cells a side: bigger ones are kept in big_ and tested directly).
  template <class F>
  void visit_keys(const Flat& t, F&& f) const {
    const glm::dvec2 lo = glm::min(glm::min(t[0], t[1]), t[2]), hi = glm::max(glm::max(t[0], t[1]), t[2]);
    const auto x0 = static_cast<std::int64_t>(std::floor(lo.x / cell_)), x1 = static_cast<std::int64_t>(std::floor(hi.x / cell_));
    const auto y0 = static_cast<std::int64_t>(std::floor(lo.y / cell_)), y1 = static_cast<std::int64_t>(std::floor(hi.y / cell_));
    for (std::int64_t y = y0; y <= y1; ++y) {
      for (std::int64_t x = x0; x <= x1; ++x) {
        f(static_cast<std::uint64_t>(x) * 0x9E3779B97F4A7C15ull ^ static_cast<std::uint64_t>(y));
      }
    }
  }
  template <class F>
  void visit(const Flat& t, F&& f) const {
    visit_keys(t, [&](std::uint64_t key) {
      const auto it = cells_.find(key);
      f(it == cells_.end() ? nullptr : &it->second);
    });
  }
  double cell_;
  std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> cells_;
  std::vector<std::uint32_t> big_, all_;
};

// Shelf packing at `scale` (uv per world unit): tallest charts first, left to right, a new shelf
// when a row is full. Returns whether everything fits in [0, 1]^2; sets each chart's origin.
bool pack(std::vector<Chart>& charts, std::span<const std::uint32_t> order, double scale, double pad) {
  double x = 0.0, y = 0.0, row = 0.0;
  for (const std::uint32_t c : order) {
    Chart& chart = charts[c];
    const double w = (chart.hi.x - chart.lo.x) * scale + pad;
    const double h = (chart.hi.y - chart.lo.y) * scale + pad;
    if (w > 1.0 || h > 1.0) return false;
    if (x + w > 1.0) {
      x = 0.0;
      y += row;
      row = 0.0;
    }
    if (y + h > 1.0) return false;
    chart.origin = glm::vec2(static_cast<float>(x), static_cast<float>(y));
    x += w;
    row = std::max(row, h);
  }
  return true;
}

constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();

// Each triangle's projection axis: the one its normal is closest to.
std::vector<int> triangle_axes(std::span<const glm::vec3> positions, std::span<const std::uint32_t> triangles) {
  const std::size_t count = triangles.size() / 3;
  std::vector<int> axis(count);
  for (std::size_t t = 0; t < count; ++t) {
    const glm::vec3 a = positions[triangles[3 * t]], b = positions[triangles[3 * t + 1]], c = positions[triangles[3 * t + 2]];
    axis[t] = dominant_axis(glm::cross(b - a, c - a));
  }
  return axis;
}

// The triangles on each edge, vertices welded by position (so UV seams of the input do not cut
// the charts): edge e of triangle t runs from corner e to corner e + 1.
struct Edges {
  std::span<const std::uint32_t> triangles;
  std::vector<std::uint32_t> weld;
  std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> triangles_on;

  [[nodiscard]] std::uint64_t key(std::size_t t, int e) const {
    std::uint32_t u = weld[triangles[3 * t + static_cast<std::size_t>(e)]];
    std::uint32_t v = weld[triangles[3 * t + static_cast<std::size_t>((e + 1) % 3)]];
    if (u > v) std::swap(u, v);
    return static_cast<std::uint64_t>(u) << 32 | v;
  }
};

Edges welded_edges(std::span<const glm::vec3> positions, std::span<const std::uint32_t> triangles) {
  Edges edges{triangles, std::vector<std::uint32_t>(positions.size()), {}};
  {
    std::unordered_map<PositionKey, std::uint32_t, PositionKeyHash> first;
    first.reserve(positions.size());
    for (std::size_t v = 0; v < positions.size(); ++v) {
      edges.weld[v] = first.try_emplace(position_key(positions[v]), static_cast<std::uint32_t>(v)).first->second;
    }
  }
  const std::size_t count = triangles.size() / 3;
  edges.triangles_on.reserve(count * 3);
  for (std::size_t t = 0; t < count; ++t) {
    for (int e = 0; e < 3; ++e) edges.triangles_on[edges.key(t, e)].push_back(static_cast<std::uint32_t>(t));
  }
  return edges;
}

// Every triangle projected on its axis, the rounding of shared vertices relative to the model's
// size (eps), and the overlap grid's cell: twice the mean projected extent.
struct Projected {
  std::vector<Flat> flats;
  double eps = 0.0;
  double cell = 1.0;
};

Projected project_triangles(std::span<const glm::vec3> positions, std::span<const std::uint32_t> triangles,
                            const std::vector<int>& axis) {
  const std::size_t count = triangles.size() / 3;
  Projected out;
  out.flats.resize(count);
  double extent_sum = 0.0;
  glm::dvec3 lo3(std::numeric_limits<double>::infinity()), hi3(-std::numeric_limits<double>::infinity());
  for (std::size_t t = 0; t < count; ++t) {
    glm::dvec2 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
    for (std::size_t k = 0; k < 3; ++k) {
      const glm::vec3& p = positions[triangles[3 * t + k]];
      out.flats[t][k] = glm::dvec2(project(p, axis[t]));
      lo = glm::min(lo, out.flats[t][k]);
      hi = glm::max(hi, out.flats[t][k]);
      lo3 = glm::min(lo3, glm::dvec3(p));
      hi3 = glm::max(hi3, glm::dvec3(p));
    }
    extent_sum += std::max(hi.x - lo.x, hi.y - lo.y);
  }
  out.eps = count == 0 ? 0.0 : 1e-7 * std::max(1e-30, glm::length(hi3 - lo3));
  out.cell = count == 0 ? 1.0 : std::max(2.0 * extent_sum / static_cast<double>(count), 1e-30);
  return out;
}

// Charts grow from a seed across shared edges to neighbours of the same axis whose projection
// does not overlap the chart's: so no chart folds onto itself, however the surface winds.
// `chart_of` gets each triangle's chart.
std::vector<Chart> grow_charts(const std::vector<int>& axis, const Edges& edges, const Projected& projected,
                               std::vector<std::uint32_t>& chart_of) {
  const std::size_t count = axis.size();
  std::vector<Chart> charts;
  chart_of.assign(count, kNone);
  ChartGrid grid(projected.cell);
  std::vector<std::uint32_t> queue;
  for (std::size_t seed = 0; seed < count; ++seed) {
    if (chart_of[seed] != kNone) continue;
    const auto c = static_cast<std::uint32_t>(charts.size());
    charts.emplace_back();
    charts.back().axis = axis[seed];
    grid.clear();
    queue.assign(1, static_cast<std::uint32_t>(seed));
    chart_of[seed] = c;
    grid.add(projected.flats[seed], static_cast<std::uint32_t>(seed));
    for (std::size_t q = 0; q < queue.size(); ++q) {
      const std::uint32_t t = queue[q];
      charts[c].triangles.push_back(t);
      for (int e = 0; e < 3; ++e) {
        const auto on = edges.triangles_on.find(edges.key(t, e));
        for (const std::uint32_t n : on->second) {
          if (chart_of[n] != kNone || axis[n] != charts[c].axis) continue;
          if (grid.overlaps(projected.flats[n], projected.flats, projected.eps)) continue;
          chart_of[n] = c;
          grid.add(projected.flats[n], n);
          queue.push_back(n);
        }
      }
    }
  }
  return charts;
}

// Each chart's projected bounds; returns the largest side of any.
double bound_charts(std::vector<Chart>& charts, std::span<const glm::vec3> positions, std::span<const std::uint32_t> triangles) {
  double largest = 0.0;
  for (Chart& chart : charts) {
    chart.lo = glm::vec2(std::numeric_limits<float>::infinity());
    chart.hi = -chart.lo;
    for (const std::uint32_t t : chart.triangles) {
      for (int k = 0; k < 3; ++k) {
        const glm::vec2 p = project(positions[triangles[3 * t + static_cast<std::size_t>(k)]], chart.axis);
        chart.lo = glm::min(chart.lo, p);
        chart.hi = glm::max(chart.hi, p);
      }
    }
    largest = std::max({largest, static_cast<double>(chart.hi.x - chart.lo.x), static_cast<double>(chart.hi.y - chart.lo.y)});
  }
  return largest;
}

// The largest scale that packs, by bisection (packing only gets harder as the scale grows), with
// the charts packed at it; fails when not even points of the charts fit.
Result<double> pack_largest(std::vector<Chart>& charts, double largest, int size, int padding) {
  std::vector<std::uint32_t> order(charts.size());
  std::iota(order.begin(), order.end(), 0u);
  std::stable_sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
    return charts[a].hi.y - charts[a].lo.y > charts[b].hi.y - charts[b].lo.y;
  });
  const double pad = static_cast<double>(padding) / static_cast<double>(size);
  if (!pack(charts, order, 0.0, pad) || !(largest > 0.0)) {
    return fail("the box-projection atlas has " + std::to_string(charts.size()) + " charts, too many for a " +
                std::to_string(size) + " x " + std::to_string(size) + " texture with " + std::to_string(padding) +
                " texels between charts: use a larger texture size, a smaller margin, or bake per vertex");
  }
  double lo = 0.0, hi = (1.0 - pad) / largest;
  if (!pack(charts, order, hi, pad)) {
    for (int i = 0; i < 48; ++i) {
      const double mid = 0.5 * (lo + hi);
      (pack(charts, order, mid, pad) ? lo : hi) = mid;
    }
    hi = lo;
  }
  pack(charts, order, hi, pad);
  return hi;
}

// The atlas mesh at `scale`: a vertex is copied once per chart that uses it.
AtlasMesh atlas_mesh(const std::vector<Chart>& charts, const std::vector<std::uint32_t>& chart_of,
                     std::span<const glm::vec3> positions, std::span<const std::uint32_t> triangles, double scale,
                     int size, int padding) {
  const double pad = static_cast<double>(padding) / static_cast<double>(size);
  AtlasMesh out;
  out.charts = charts.size();
  out.texels_per_unit = static_cast<float>(scale * size);
  out.triangles.resize(triangles.size());
  std::unordered_map<std::uint64_t, std::uint32_t> copy;
  for (std::size_t t = 0; t < triangles.size() / 3; ++t) {
    const Chart& chart = charts[chart_of[t]];
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t v = triangles[3 * t + static_cast<std::size_t>(k)];
      const std::uint64_t key = static_cast<std::uint64_t>(chart_of[t]) << 32 | v;
      auto [it, added] = copy.emplace(key, static_cast<std::uint32_t>(out.source_vertex.size()));
      if (added) {
        const glm::vec2 p = project(positions[v], chart.axis);
        const glm::dvec2 uv = glm::dvec2(chart.origin) + 0.5 * pad + glm::dvec2(p - chart.lo) * scale;
        out.source_vertex.push_back(v);
        out.uv.push_back(glm::clamp(glm::vec2(uv), glm::vec2(0.0f), glm::vec2(1.0f)));
      }
      out.triangles[3 * t + static_cast<std::size_t>(k)] = it->second;
    }
  }
  return out;
}

}  // namespace

Result<AtlasMesh> box_atlas(std::span<const glm::vec3> positions, std::span<const std::uint32_t> triangles, int size,
                            int padding) {
  const std::vector<int> axis = triangle_axes(positions, triangles);
  const Edges edges = welded_edges(positions, triangles);
  const Projected projected = project_triangles(positions, triangles, axis);
  std::vector<std::uint32_t> chart_of;
  std::vector<Chart> charts = grow_charts(axis, edges, projected, chart_of);
  const double largest = bound_charts(charts, positions, triangles);
  Result<double> scale = pack_largest(charts, largest, size, padding);
  if (!scale) return std::unexpected(scale.error());
  return atlas_mesh(charts, chart_of, positions, triangles, *scale, size, padding);
}

}  // namespace exao::bake
