#include "bake/box_atlas.h"

#include <algorithm>
#include <limits>
#include <numeric>
#include <unordered_map>

namespace exao::bake {
namespace {

struct UnionFind {
  std::vector<std::uint32_t> parent;
  explicit UnionFind(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0u); }
  std::uint32_t find(std::uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  }
  void join(std::uint32_t a, std::uint32_t b) { parent[find(a)] = find(b); }
};

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

}  // namespace

Result<AtlasMesh> box_atlas(std::span<const glm::vec3> positions, std::span<const std::uint32_t> triangles, int size,
                            int padding) {
  const std::size_t count = triangles.size() / 3;
  std::vector<int> axis(count);
  for (std::size_t t = 0; t < count; ++t) {
    const glm::vec3 a = positions[triangles[3 * t]], b = positions[triangles[3 * t + 1]], c = positions[triangles[3 * t + 2]];
    axis[t] = dominant_axis(glm::cross(b - a, c - a));
  }
  // Charts: triangles of one axis that share an edge.
  UnionFind sets(count);
  std::unordered_map<std::uint64_t, std::uint32_t> edge_owner;
  edge_owner.reserve(count * 3);
  for (std::size_t t = 0; t < count; ++t) {
    for (int e = 0; e < 3; ++e) {
      std::uint32_t u = triangles[3 * t + static_cast<std::size_t>(e)];
      std::uint32_t v = triangles[3 * t + static_cast<std::size_t>((e + 1) % 3)];
      if (u > v) std::swap(u, v);
      // Keyed by axis too, so only same-axis neighbours join.
      const std::uint64_t key = (static_cast<std::uint64_t>(u) << 32 | v) * 6u + static_cast<std::uint64_t>(axis[t]);
      const auto [it, added] = edge_owner.emplace(key, static_cast<std::uint32_t>(t));
      if (!added) sets.join(static_cast<std::uint32_t>(t), it->second);
    }
  }
  std::vector<Chart> charts;
  std::unordered_map<std::uint32_t, std::uint32_t> chart_of_root;
  std::vector<std::uint32_t> chart_of(count);
  for (std::size_t t = 0; t < count; ++t) {
    const std::uint32_t root = sets.find(static_cast<std::uint32_t>(t));
    auto [it, added] = chart_of_root.emplace(root, static_cast<std::uint32_t>(charts.size()));
    if (added) {
      charts.emplace_back();
      charts.back().axis = axis[t];
    }
    chart_of[t] = it->second;
    charts[it->second].triangles.push_back(static_cast<std::uint32_t>(t));
  }
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
  std::vector<std::uint32_t> order(charts.size());
  std::iota(order.begin(), order.end(), 0u);
  std::stable_sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
    return charts[a].hi.y - charts[a].lo.y > charts[b].hi.y - charts[b].lo.y;
  });

  // The largest scale that packs, by bisection: packing only gets harder as the scale grows.
  const double pad = static_cast<double>(padding) / static_cast<double>(size);
  if (!pack(charts, order, 0.0, pad) || !(largest > 0.0)) {
    return fail("the box-projection atlas has " + std::to_string(charts.size()) + " charts, too many for a " +
                std::to_string(size) + " x " + std::to_string(size) + " texture with " + std::to_string(padding) +
                " texels between charts: use a larger --texture, a smaller --margin, or --vertex");
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

  AtlasMesh out;
  out.charts = charts.size();
  out.texels_per_unit = static_cast<float>(hi * size);
  out.triangles.resize(triangles.size());
  // A vertex is copied once per chart that uses it.
  std::unordered_map<std::uint64_t, std::uint32_t> copy;
  for (std::size_t t = 0; t < count; ++t) {
    const Chart& chart = charts[chart_of[t]];
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t v = triangles[3 * t + static_cast<std::size_t>(k)];
      const std::uint64_t key = static_cast<std::uint64_t>(chart_of[t]) << 32 | v;
      auto [it, added] = copy.emplace(key, static_cast<std::uint32_t>(out.source_vertex.size()));
      if (added) {
        const glm::vec2 p = project(positions[v], chart.axis);
        const glm::dvec2 uv = glm::dvec2(chart.origin) + 0.5 * pad + glm::dvec2(p - chart.lo) * hi;
        out.source_vertex.push_back(v);
        out.uv.push_back(glm::clamp(glm::vec2(uv), glm::vec2(0.0f), glm::vec2(1.0f)));
      }
      out.triangles[3 * t + static_cast<std::size_t>(k)] = it->second;
    }
  }
  return out;
}

}  // namespace exao::bake
