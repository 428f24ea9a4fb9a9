#include "raster/lod.h"

#include <array>
#include <chrono>
#include <cmath>
#include <numeric>
#include <unordered_map>

#include <tbb/parallel_for.h>

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/repair_polygon_soup.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/Bounded_distance_placement.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/Count_stop_predicate.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/LindstromTurk_cost.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/LindstromTurk_placement.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/Polyhedral_envelope_filter.h>
#include <CGAL/Surface_mesh_simplification/edge_collapse.h>

#include "core/position_key.h"

namespace exao::raster {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Mesh = CGAL::Surface_mesh<Point>;
using Polygon = std::array<std::size_t, 3>;
namespace PMP = CGAL::Polygon_mesh_processing;
namespace SMS = CGAL::Surface_mesh_simplification;

double elapsed(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// Union-find over triangles.
struct Components {
  std::vector<std::uint32_t> parent;
  explicit Components(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0u); }
  std::uint32_t find(std::uint32_t a) {
    while (parent[a] != a) a = parent[a] = parent[parent[a]];
    return a;
  }
  void join(std::uint32_t a, std::uint32_t b) {
    a = find(a);
    b = find(b);
    if (a != b) parent[std::max(a, b)] = std::min(a, b);
  }
};

// One simplifiable component as a mesh. Each is simplified on its own: its envelope holds only
// its own faces, which keeps the envelope's queries cheap (one envelope around a whole scene
// of small parts answers every query with many overlapping prisms), and components run in
// parallel.
struct Group {
  bool two_sided = false;
  Mesh mesh;
};

void simplify(Mesh& mesh, double eps, LodFilter filter) {
  SMS::Count_stop_predicate<Mesh> stop(0);  // until no collapse is allowed
  using Cost = SMS::LindstromTurk_cost<Mesh>;
  using Placement = SMS::LindstromTurk_placement<Mesh>;
  if (filter == LodFilter::Envelope) {
    SMS::Polyhedral_envelope_filter<Kernel> envelope(eps);
    SMS::edge_collapse(mesh, stop, CGAL::parameters::get_cost(Cost()).get_placement(Placement()).filter(envelope));
  } else {
    SMS::Bounded_distance_placement<Placement, Kernel> placement(eps);
    SMS::edge_collapse(mesh, stop, CGAL::parameters::get_cost(Cost()).get_placement(placement));
  }
  mesh.collect_garbage();
}

void append_mesh(const Mesh& mesh, bool two_sided, Scene& out) {
  for (const auto f : mesh.faces()) {
    for (const auto v : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) {
      const Point& p = mesh.point(v);
      out.vertices.emplace_back(static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z()));
    }
    out.two_sided.push_back(two_sided ? 1 : 0);
    out.material.push_back(-1);
  }
}

}  // namespace

Result<LodFilter> parse_lod_filter(const std::string& name) {
  if (const std::optional<LodFilter> f = parse_enum<LodFilter>(name)) return *f;
  return fail("lod_filter: unknown filter '" + name + "' (" + name_list<LodFilter>() + ")");
}

const char* lod_filter_name(LodFilter filter) { return name_of(filter); }

Result<void> check_lod_options(const LodOptions& options) {
  if (!(options.eps1 > 0.0f) || !std::isfinite(options.eps1)) {
    return fail("lod_eps1: must be a positive length, not " + std::to_string(options.eps1));
  }
  if (options.levels < 1 || options.levels > 8) {
    return fail("lod_levels: must be 1 to 8, not " + std::to_string(options.levels));
  }
  if (!(options.k > 0.0f) || !std::isfinite(options.k)) {
    return fail("lod_k: must be a positive number, not " + std::to_string(options.k));
  }
  if (!(options.overlap >= 0.0f) || !(options.overlap < options.k)) {
    return fail("lod_overlap: must be at least 0 and less than lod_k, not " + std::to_string(options.overlap));
  }
  return {};
}

float auto_lod_eps(float radius, float footprint, int levels, float k) {
  // Measured on Conference at r = 5% (docs/raster-lod.md): one level with level 0 up to about
  // r / 9 keeps 97% of the pixels identical at 4x the speed; more levels or a larger eps_1 lose
  // thin distant occluders. `levels` is accepted for the contract, the rule does not use it.
  static_cast<void>(levels);
  const float wanted = std::max(radius / (9.0f * k), 2.0f * footprint);
  // Down to a power of 3: levels of eps_1 3^j serve each other (assemble_lod), so nearby radii
  // and views share one simplification.
  return std::pow(3.0f, std::floor(std::log(wanted) / std::log(3.0f) + 1e-4f));
}

namespace {

// Exact duplicate vertices of triangles of the same sidedness become one: `corner` gives each of
// the scene's 3n corners its welded vertex.
struct Welded {
  std::vector<std::uint32_t> corner;
  std::vector<glm::vec3> vertices;
};

Welded weld_corners(const Scene& scene) {
  const std::size_t n = scene.triangle_count();
  Welded w;
  w.corner.resize(3 * n);
  std::unordered_map<PositionKey, std::uint32_t, PositionKeyHash> ids[2];
  for (std::size_t t = 0; t < n; ++t) {
    auto& map = ids[scene.two_sided[t] ? 1 : 0];
    for (int c = 0; c < 3; ++c) {
      const glm::vec3& v = scene.vertices[3 * t + static_cast<std::size_t>(c)];
      const auto [it, added] = map.try_emplace(position_key(v), static_cast<std::uint32_t>(w.vertices.size()));
      if (added) w.vertices.push_back(v);
      w.corner[3 * t + static_cast<std::size_t>(c)] = it->second;
    }
  }
  return w;
}

// Components: triangles sharing a welded vertex. `order` lists the triangles component by
// component (stable within one), `root` names each triangle's component.
struct ComponentOrder {
  std::vector<std::uint32_t> order;
  std::vector<std::uint32_t> root;
};

ComponentOrder component_order(const Welded& w, std::size_t n) {
  Components uf(n);
  std::vector<std::uint32_t> first(w.vertices.size(), UINT32_MAX);
  for (std::size_t t = 0; t < n; ++t) {
    for (int c = 0; c < 3; ++c) {
      std::uint32_t& f = first[w.corner[3 * t + static_cast<std::size_t>(c)]];
      if (f == UINT32_MAX) f = static_cast<std::uint32_t>(t);
      else uf.join(f, static_cast<std::uint32_t>(t));
    }
  }
  ComponentOrder out;
  out.order.resize(n);
  std::iota(out.order.begin(), out.order.end(), 0u);
  out.root.resize(n);
  for (std::size_t t = 0; t < n; ++t) out.root[t] = uf.find(static_cast<std::uint32_t>(t));
  std::stable_sort(out.order.begin(), out.order.end(),
                   [&](std::uint32_t a, std::uint32_t b) { return out.root[a] < out.root[b]; });
  return out;
}

// Per component: repair, orient, decide; the simplifiable ones into their group (largest first),
// the others kept at full detail in `lod`.
std::vector<Group> component_groups(const Scene& scene, const Welded& w, const ComponentOrder& components, LodChain& lod) {
  const std::size_t n = scene.triangle_count();
  const std::vector<std::uint32_t>& order = components.order;
  const std::vector<std::uint32_t>& root = components.root;
  std::vector<std::uint8_t>& kept = lod.kept;
  std::vector<Group> groups;
  std::unordered_map<std::uint32_t, std::size_t> local;
  for (std::size_t begin = 0; begin < n;) {
    std::size_t end = begin;
    while (end < n && root[order[end]] == root[order[begin]]) ++end;
    ++lod.components;
    const bool two_sided = scene.two_sided[order[begin]] != 0;
    std::vector<Point> points;
    std::vector<Polygon> polygons;
    local.clear();
    for (std::size_t i = begin; i < end; ++i) {
      Polygon polygon;
      for (int c = 0; c < 3; ++c) {
        const std::uint32_t id = w.corner[3 * std::size_t{order[i]} + static_cast<std::size_t>(c)];
        const auto [it, added] = local.try_emplace(id, points.size());
        if (added) points.emplace_back(w.vertices[id].x, w.vertices[id].y, w.vertices[id].z);
        polygon[static_cast<std::size_t>(c)] = it->second;
      }
      polygons.push_back(polygon);
    }
    PMP::repair_polygon_soup(points, polygons);
    bool ok = !polygons.empty();
    if (ok && two_sided) {
      // orient_polygon_soup returns false when it had to split a vertex or an edge that is not
      // manifold; the split soup is then a manifold surface with the same triangles, which for
      // two-sided triangles blocks the same rays, so it is simplified like any other.
      lod.split_components += PMP::orient_polygon_soup(points, polygons) ? 0 : 1;
    }
    if (ok) ok = PMP::is_polygon_soup_a_polygon_mesh(polygons);
    if (!ok) {
      ++lod.kept_components;
      for (std::size_t i = begin; i < end; ++i) kept[order[i]] = 1;
      lod.kept_triangles += end - begin;
    } else {
      Group& g = groups.emplace_back();
      g.two_sided = two_sided;
      PMP::polygon_soup_to_polygon_mesh(points, polygons, g.mesh);
    }
    begin = end;
  }
  std::stable_sort(groups.begin(), groups.end(),
                   [](const Group& a, const Group& b) { return a.mesh.number_of_faces() > b.mesh.number_of_faces(); });
  return groups;
}

// The lines that tell the user which components were split or kept.
void add_component_notes(LodChain& lod) {
  if (lod.split_components > 0) {
    lod.notes.push_back(std::to_string(lod.split_components) + " of " + std::to_string(lod.components) +
                        " two-sided components had non-manifold vertices or edges: split by orient_polygon_soup, "
                        "then simplified");
  }
  if (lod.kept_components > 0) {
    lod.notes.push_back(std::to_string(lod.kept_components) + " of " + std::to_string(lod.components) +
                        " components (" + std::to_string(lod.kept_triangles) +
                        " triangles) are not manifold surfaces after welding and orienting (one-sided ones are never "
                        "re-oriented): kept at full detail");
  }
}

// Levels 1..L, each simplified from the one before.
void simplify_levels(std::vector<Group>& groups, float eps1, int levels, LodFilter filter, const ProgressCallback& progress,
                     LodChain& lod) {
  ProgressCounter counter(progress, static_cast<std::size_t>(levels));
  double previous = 0.0;
  for (int i = 1; i <= levels; ++i) {
    const auto level_start = std::chrono::steady_clock::now();
    const double eps = double(eps1) * std::pow(3.0, i - 1);
    // Largest components first, so that one big part does not finish last alone.
    tbb::parallel_for(std::size_t{0}, groups.size(), [&](std::size_t g) {
      if (groups[g].mesh.number_of_faces() > 1) simplify(groups[g].mesh, eps - previous, filter);
    });
    previous = eps;
    Scene& level = lod.levels.emplace_back();
    for (const Group& g : groups) append_mesh(g.mesh, g.two_sided, level);
    lod.level_seconds.push_back(elapsed(level_start));
    counter.add(1);
  }
}

}  // namespace

Result<LodChain> build_lod_chain(const Scene& scene, float eps1, int levels, LodFilter filter,
                                 const ProgressCallback& progress) {
  LodOptions check;
  check.eps1 = eps1;
  if (auto ok = check_lod_options(check); !ok) return std::unexpected(ok.error());
  if (levels < 0) return fail("lod_levels: must be at least 0, not " + std::to_string(levels));
  const auto start = std::chrono::steady_clock::now();
  const Welded welded = weld_corners(scene);
  const ComponentOrder components = component_order(welded, scene.triangle_count());
  LodChain lod;
  lod.eps1 = eps1;
  lod.filter = filter;
  lod.kept.assign(scene.triangle_count(), 0);
  std::vector<Group> groups = component_groups(scene, welded, components, lod);
  add_component_notes(lod);
  simplify_levels(groups, eps1, levels, filter, progress, lod);
  lod.seconds = elapsed(start);
  return lod;
}

Result<LodScene> assemble_lod(const Scene& scene, const LodChain& chain, float radius, const LodOptions& options) {
  if (auto ok = check_lod_options(options); !ok) return std::unexpected(ok.error());
  if (!(radius > 0.0f) || !std::isfinite(radius)) return fail("radius: must be positive, not " + std::to_string(radius));
  // options.eps1 = chain.eps1 * 3^first.
  const double ratio = std::log(double(options.eps1) / double(chain.eps1)) / std::log(3.0);
  const int first = static_cast<int>(std::lround(ratio));
  if (first < 0 || std::abs(ratio - first) > 1e-3) {
    return fail("lod_eps1: " + std::to_string(options.eps1) + " is not the chain's eps_1 times a power of 3");
  }
  const auto start = std::chrono::steady_clock::now();
  const std::size_t n = scene.triangle_count();
  LodScene lod;
  lod.components = chain.components;
  lod.split_components = chain.split_components;
  lod.kept_components = chain.kept_components;
  lod.kept_triangles = chain.kept_triangles;
  lod.notes = chain.notes;
  const std::vector<std::uint8_t>& kept = chain.kept;

  // --- The ranges of the levels that are built: r_min = k eps_i < r. Each boundary is computed
  // once, so that one level's r_max is bit for bit the next level's r_min. ---
  std::vector<float> eps{0.0f};
  std::vector<float> boundary{0.0f};
  for (int i = 1; i <= options.levels; ++i) {
    const float e = options.eps1 * std::pow(3.0f, static_cast<float>(i - 1));
    if (!(options.k * e < radius)) break;
    eps.push_back(e);
    boundary.push_back(options.k * e);
  }
  boundary.push_back(radius);  // the last level reaches r
  const int levels = static_cast<int>(eps.size()) - 1;
  if (first + levels > static_cast<int>(chain.levels.size())) {
    return fail("lod_levels: the chain has " + std::to_string(chain.levels.size()) + " levels, " +
                std::to_string(first + levels) + " are needed");
  }
  auto range_of = [&](int i) {
    const auto u = static_cast<std::size_t>(i);
    return DistanceRange{i == 0 ? 0.0f : boundary[u] - options.overlap * eps[u], boundary[u + 1]};
  };

  // --- Level 0: the scene itself. ---
  Scene all;
  all.vertices = scene.vertices;
  all.two_sided = scene.two_sided;
  all.material.assign(n, -1);
  lod.ranges.resize(n);
  lod.level.assign(n, 0);
  const DistanceRange range0 = range_of(0);
  for (std::size_t t = 0; t < n; ++t) lod.ranges[t] = kept[t] ? DistanceRange{0.0f, radius} : range0;
  lod.levels.push_back({0.0f, range0, n, 0.0});
  // --- Levels 1..L: the chain's levels first .. first + L - 1. ---
  for (int i = 1; i <= levels; ++i) {
    const Scene& level = chain.levels[static_cast<std::size_t>(first + i - 1)];
    all.vertices.insert(all.vertices.end(), level.vertices.begin(), level.vertices.end());
    all.two_sided.insert(all.two_sided.end(), level.two_sided.begin(), level.two_sided.end());
    all.material.resize(all.two_sided.size(), -1);
    lod.ranges.resize(all.triangle_count(), range_of(i));
    lod.level.resize(all.triangle_count(), static_cast<std::uint8_t>(i));
    lod.levels.push_back({eps[static_cast<std::size_t>(i)], range_of(i), level.triangle_count(),
                          chain.level_seconds[static_cast<std::size_t>(first + i - 1)]});
  }
  lod.triangles = lut::TriangleSet::build(all);
  lod.seconds = chain.seconds + elapsed(start);
  return lod;
}

Result<LodScene> build_lod(const Scene& scene, float radius, const LodOptions& options, const ProgressCallback& progress) {
  if (auto ok = check_lod_options(options); !ok) return std::unexpected(ok.error());
  if (!(radius > 0.0f) || !std::isfinite(radius)) return fail("radius: must be positive, not " + std::to_string(radius));
  int levels = 0;
  while (levels < options.levels && options.k * options.eps1 * std::pow(3.0f, static_cast<float>(levels)) < radius) ++levels;
  Result<LodChain> chain = build_lod_chain(scene, options.eps1, levels, options.filter, progress);
  if (!chain) return std::unexpected(chain.error());
  return assemble_lod(scene, *chain, radius, options);
}

std::vector<glm::vec3> level_triangles(const LodScene& lod, int i, bool simplifiable_only) {
  std::vector<glm::vec3> out;
  const float radius_cap = i == 0 && lod.levels.size() > 1 ? lod.levels[0].range.r_max : -1.0f;
  for (std::size_t t = 0; t < lod.level.size(); ++t) {
    if (lod.level[t] != i) continue;
    if (simplifiable_only && radius_cap >= 0.0f && lod.ranges[t].r_max != radius_cap) continue;
    out.push_back(lod.triangles.v0[t]);
    out.push_back(lod.triangles.v1[t]);
    out.push_back(lod.triangles.v2[t]);
  }
  return out;
}

double sampled_distance(std::span<const glm::vec3> from, std::span<const glm::vec3> to, int samples_per_triangle) {
  using Triangle = Kernel::Triangle_3;
  using Primitive = CGAL::AABB_triangle_primitive<Kernel, std::vector<Triangle>::const_iterator>;
  using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;
  auto point = [](const glm::vec3& v) { return Point(v.x, v.y, v.z); };
  std::vector<Triangle> triangles;
  for (std::size_t i = 0; i + 2 < to.size(); i += 3) {
    const Triangle tri(point(to[i]), point(to[i + 1]), point(to[i + 2]));
    if (!tri.is_degenerate()) triangles.push_back(tri);
  }
  if (triangles.empty()) return std::numeric_limits<double>::infinity();
  Tree tree(triangles.begin(), triangles.end());
  tree.accelerate_distance_queries();
  double worst = 0.0;
  auto probe = [&](const glm::dvec3& p) { worst = std::max(worst, tree.squared_distance(Point(p.x, p.y, p.z))); };
  // Stratified barycentric points: the R2 sequence folded into the triangle.
  constexpr double g1 = 0.7548776662466927, g2 = 0.5698402909980532;
  for (std::size_t i = 0; i + 2 < from.size(); i += 3) {
    const glm::dvec3 a(from[i]), b(from[i + 1]), c(from[i + 2]);
    for (const glm::dvec3& p : {a, b, c, 0.5 * (a + b), 0.5 * (b + c), 0.5 * (c + a)}) probe(p);
    for (int s = 0; s < samples_per_triangle; ++s) {
      double u = std::fmod(0.5 + g1 * (s + 1), 1.0), v = std::fmod(0.5 + g2 * (s + 1), 1.0);
      if (u + v > 1.0) {
        u = 1.0 - u;
        v = 1.0 - v;
      }
      probe(a + u * (b - a) + v * (c - a));
    }
  }
  return std::sqrt(worst);
}

}  // namespace exao::raster
