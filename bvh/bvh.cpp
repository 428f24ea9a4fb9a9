#include "bvh/bvh.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>
#include <tbb/task_group.h>

#include "bvh/sah_builder.h"
#include "core/check.h"
#include "core/huge_pages.h"

namespace exao::bvh {
namespace {

constexpr std::size_t kGrain = 1 << 14;

// Whether any triangle belongs to an object other than 0 (else the tree keeps no objects).
bool any_object(const std::vector<std::uint32_t>& object) {
  return std::any_of(object.begin(), object.end(), [](std::uint32_t o) { return o != 0; });
}

// Where the triangles come from: a TriangleSet (spheres already computed) or a Scene (computed
// here by the same function, so the floats are the same).
struct SetSource {
  const lut::TriangleSet& set;
  [[nodiscard]] std::size_t size() const { return set.size(); }
  [[nodiscard]] glm::vec3 vertex(std::size_t t, int k) const { return k == 0 ? set.v0[t] : k == 1 ? set.v1[t] : set.v2[t]; }
  [[nodiscard]] lut::PackedTriangle packed(std::size_t t) const { return set.packed(t); }
  [[nodiscard]] bool has_objects() const { return any_object(set.object); }
  [[nodiscard]] std::uint32_t object(std::size_t t) const { return set.object[t]; }
  [[nodiscard]] std::shared_ptr<const Cutouts> cutouts() const { return set.cutouts; }
  void release() const {}
};

struct SceneSource {
  const Scene& scene;
  Scene* owned = nullptr;  // the caller's scene to free once the leaf blocks are made, or null
  [[nodiscard]] std::size_t size() const { return scene.triangle_count(); }
  [[nodiscard]] glm::vec3 vertex(std::size_t t, int k) const { return scene.vertices[3 * t + static_cast<std::size_t>(k)]; }
  [[nodiscard]] lut::PackedTriangle packed(std::size_t t) const {
    lut::PackedTriangle p;
    p.v0 = scene.vertices[3 * t];
    p.v1 = scene.vertices[3 * t + 1];
    p.v2 = scene.vertices[3 * t + 2];
    lut::bounding_sphere(p.v0, p.v1, p.v2, p.centre, p.radius);
    p.two_sided = scene.two_sided[t];
    p.cutout = scene.cutouts && scene.cutouts->any() && scene.cutouts->tests(t) ? 1u : 0u;
    p.object = t < scene.object.size() ? scene.object[t] : 0u;
    return p;
  }
  [[nodiscard]] bool has_objects() const { return any_object(scene.object); }
  [[nodiscard]] std::uint32_t object(std::size_t t) const { return t < scene.object.size() ? scene.object[t] : 0u; }
  [[nodiscard]] std::shared_ptr<const Cutouts> cutouts() const {
    return scene.cutouts && scene.cutouts->any() ? scene.cutouts : nullptr;
  }
  // The leaf blocks hold every float the tree needs from here on.
  void release() const {
    if (owned) *owned = Scene{};
  }
};

// The farthest reach from `centre` of a triangle sphere of the leaf: |c - centre| + r, at least
// `found`.
double leaf_reach(const LeafBlock& leaf, const glm::dvec3& centre, double found) {
  for (int l = 0; l < static_cast<int>(leaf.count); ++l) {
    const glm::dvec3 c(leaf.cx()[l], leaf.cy()[l], leaf.cz()[l]);
    found = std::max(found, glm::length(c - centre) + double(leaf.radius()[l]));
  }
  return found;
}

// The same over every leaf below node `index`, whose spheres are set. A child's sphere holds
// every triangle sphere below it, so |its centre - centre| + its radius bounds their reach:
// a child whose bound is no farther than the reach found so far is not opened, and the result
// is the same maximum as a visit of every triangle. The bound is computed in doubles from
// floats, as the reaches are, and a child's radius carries a relative margin of 1e-6 (set_sphere),
// so a factor of 1 + 1e-12 covers the rounding of both.
double subtree_reach(const Bvh& bvh, std::uint32_t index, const glm::dvec3& centre, double found) {
  const Node& node = bvh.nodes[index];
  const int count = std::min<int>(node.child_count, kMaxChildren);
  int order[kMaxChildren];
  double bound[kMaxChildren];
  for (int k = 0; k < count; ++k) {
    const glm::dvec3 c(node.centre_x[k], node.centre_y[k], node.centre_z[k]);
    bound[k] = glm::length(c - centre) + double(node.radius[k]);
    order[k] = k;
  }
  // Farthest first, so that the nearer children are pruned by what it finds (the order changes
  // only how much is pruned, never the maximum).
  for (int i = 1; i < count; ++i)
    for (int j = i; j > 0 && bound[order[j]] > bound[order[j - 1]]; --j) std::swap(order[j], order[j - 1]);
  for (int i = 0; i < count; ++i) {
    const int k = order[i];
    if (bound[k] * (1.0 + 1e-12) <= found) continue;
    found = node.leaf_size[k] != 0 ? leaf_reach(bvh.leaf_at(node.child[k]), centre, found)
                                   : subtree_reach(bvh, node.child[k], centre, found);
  }
  return found;
}

// A sphere around the box centre of slot `slot` holding every triangle sphere below it (tighter
// than the box's circumsphere), radius rounded up past the float centre: the region mask of
// this sphere must contain those of the triangles' spheres (lut/sphere_test.h, nesting). A
// child node's spheres must be set first.
void set_sphere(Node& node, int slot, const Bvh& bvh) {
  const glm::vec3 centre_f(0.5f * (node.lo_x[slot] + node.hi_x[slot]), 0.5f * (node.lo_y[slot] + node.hi_y[slot]),
                           0.5f * (node.lo_z[slot] + node.hi_z[slot]));
  const glm::dvec3 centre(centre_f);
  const double radius = node.leaf_size[slot] != 0 ? leaf_reach(bvh.leaf_at(node.child[slot]), centre, 0.0)
                                                  : subtree_reach(bvh, node.child[slot], centre, 0.0);
  node.centre_x[slot] = centre_f.x;
  node.centre_y[slot] = centre_f.y;
  node.centre_z[slot] = centre_f.z;
  node.radius[slot] = std::nextafter(static_cast<float>(radius * (1.0 + 1e-6)), INFINITY);
}

// Every sphere of the subtree of node `index`, children before their parent; large subtrees'
// children in parallel (`depth` levels below the root).
void set_spheres(Bvh& bvh, std::uint32_t index, int depth) {
  Node& node = bvh.nodes[index];
  constexpr int kParallelDepth = 6;  // 4^6 tasks at most: enough for any core count here
  const auto below = [&](int k) {
    if (node.leaf_size[k] == 0) set_spheres(bvh, node.child[k], depth + 1);
  };
  if (depth < kParallelDepth) {
    tbb::task_group group;
    for (int k = 0; k < node.child_count; ++k) group.run([&, k] { below(k); });
    group.wait();
  } else {
    for (int k = 0; k < node.child_count; ++k) below(k);
  }
  for (int k = 0; k < node.child_count; ++k) set_sphere(node, k, bvh);
}

// Lane l of the rows at `rows` (of `width` floats each, LeafRow's order).
void put_lane(float* rows, int width, int l, const glm::vec3& v0, const glm::vec3& v1, const glm::vec3& v2,
              const glm::vec3& centre, float radius) {
  const float values[kLeafRows] = {v0.x, v0.y, v0.z, v1.x, v1.y, v1.z, v2.x, v2.y, v2.z, centre.x, centre.y, centre.z, radius};
  for (int r = 0; r < kLeafRows; ++r) rows[r * width + l] = values[r];
}

// The header and rows of the leaf of triangles [first, first + size), from the source's
// triangles in the tree's order, at `place`; lanes past the leaf NaN. Returns the largest
// |coordinate| of its vertices.
template <class Source>
float make_leaf(const Source& source, const std::vector<std::uint32_t>& order, std::uint32_t first, int size,
                float* place) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const int width = leaf_width(size);
  float* rows = place + kLeafHeaderFloats;
  LeafHeader header{};
  header.first = first;
  header.count = static_cast<std::uint8_t>(size);
  float largest = 0.0f;
  for (int l = 0; l < width; ++l) {
    if (l >= size) {
      const glm::vec3 none(nan);
      put_lane(rows, width, l, none, none, none, none, nan);
      continue;
    }
    const lut::PackedTriangle t = source.packed(order[first + static_cast<std::uint32_t>(l)]);
    put_lane(rows, width, l, t.v0, t.v1, t.v2, t.centre, t.radius);
    if (t.two_sided) header.two_sided |= static_cast<std::uint8_t>(1u << l);
    if (t.cutout) header.cutout |= static_cast<std::uint8_t>(1u << l);
    for (const glm::vec3& v : {t.v0, t.v1, t.v2}) largest = std::max({largest, std::abs(v.x), std::abs(v.y), std::abs(v.z)});
  }
  std::memcpy(place, &header, sizeof header);
  return largest;
}

// The tree's shape over the source's triangles' boxes; the boxes (32 bytes a triangle) are freed
// before the leaves are made.
template <class Source>
Result<Topology> topology_of(const Source& source, const BvhOptions& options, const ProgressCallback& progress) {
  const std::size_t n = source.size();
  BuildPrimitives primitives;
  reserve_huge(primitives, n);
  primitives.resize(n);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, kGrain), [&](const tbb::blocked_range<std::size_t>& range) {
    for (std::size_t t = range.begin(); t != range.end(); ++t) {
      const glm::vec3 a = source.vertex(t, 0), b = source.vertex(t, 1), c = source.vertex(t, 2);
      const glm::vec3 lo = glm::min(a, glm::min(b, c)), hi = glm::max(a, glm::max(b, c));
      primitives[t] = {lo.x, lo.y, lo.z, static_cast<std::uint32_t>(t), hi.x, hi.y, hi.z, 0.0f};
    }
  });
  return build_topology(primitives, options, {}, progress);
}

// Where each node's leaves start in leaf_floats (node order, then slot order), one past the last
// node's the total; counts the leaves.
Result<std::vector<std::uint64_t>> leaf_places(Bvh& bvh) {
  std::vector<std::uint64_t> first_float(bvh.nodes.size() + 1, 0);
  for (std::size_t i = 0; i < bvh.nodes.size(); ++i) {
    const Node& node = bvh.nodes[i];
    std::uint64_t floats = 0;
    for (int k = 0; k < node.child_count; ++k) {
      if (node.leaf_size[k] == 0) continue;
      ++bvh.leaf_count;
      floats += static_cast<std::uint64_t>(leaf_floats_of(node.leaf_size[k]));
    }
    first_float[i + 1] = first_float[i] + floats;
  }
  if (first_float.back() > std::numeric_limits<std::uint32_t>::max()) {
    return fail("bvh: " + std::to_string(bvh.scene_triangle.size()) +
                " triangles need more leaf floats than 32-bit offsets address");
  }
  return first_float;
}

// Every leaf's header and rows at its place; a leaf slot's child becomes that place (it was the
// leaf's first triangle, which the header keeps). Sets largest_coordinate; progress from n to 2n.
template <class Source>
void make_leaves(const Source& source, const std::vector<std::uint64_t>& first_float, Bvh& bvh,
                 const ProgressCallback& progress) {
  const std::size_t n = bvh.scene_triangle.size();
  reserve_huge(bvh.leaf_floats, first_float.back());
  bvh.leaf_floats.resize(first_float.back());  // unwritten until make_leaf writes every float
  std::atomic<std::size_t> placed{0};
  bvh.largest_coordinate = tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, bvh.nodes.size(), 256), 0.0f,
      [&](const tbb::blocked_range<std::size_t>& range, float largest) {
        std::size_t triangles = 0;
        for (std::size_t i = range.begin(); i != range.end(); ++i) {
          Node& node = bvh.nodes[i];
          auto place = static_cast<std::uint32_t>(first_float[i]);
          for (int k = 0; k < node.child_count; ++k) {
            const int size = node.leaf_size[k];
            if (size == 0) continue;
            const std::uint32_t first = node.child[k];
            largest = std::max(largest, make_leaf(source, bvh.scene_triangle, first, size, bvh.leaf_floats.data() + place));
            node.child[k] = place;
            triangles += static_cast<std::size_t>(size);
            place += static_cast<std::uint32_t>(leaf_floats_of(size));
          }
        }
        if (progress) progress(n + (placed += triangles), 2 * n);
        return largest;
      },
      [](float x, float y) { return std::max(x, y); });
}

template <class Source>
Result<Bvh> build_from(const Source& source, const BvhOptions& options, const ProgressCallback& progress) {
  const std::size_t n = source.size();
  if (n == 0) return fail("bvh: the scene has no triangles");
  if (auto ok = check_options(options); !ok) return std::unexpected(ok.error());
  // Progress: the topology reports n (triangles placed in leaves), the leaves n more.
  const ProgressCallback topology_progress =
      progress ? ProgressCallback([&](std::size_t done, std::size_t) { progress(done, 2 * n); }) : ProgressCallback();
  Result<Topology> topology = topology_of(source, options, topology_progress);
  if (!topology) return std::unexpected(topology.error());

  Bvh bvh;
  bvh.cutouts = source.cutouts();
  bvh.nodes = std::move(topology->nodes);
  bvh.scene_triangle = std::move(topology->order);
  if (source.has_objects()) {
    bvh.object.resize(n);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, kGrain), [&](const tbb::blocked_range<std::size_t>& range) {
      for (std::size_t i = range.begin(); i != range.end(); ++i) bvh.object[i] = source.object(bvh.scene_triangle[i]);
    });
  }
  Result<std::vector<std::uint64_t>> first_float = leaf_places(bvh);
  if (!first_float) return std::unexpected(first_float.error());
  make_leaves(source, *first_float, bvh, progress);
  source.release();
  set_spheres(bvh, 0, 0);
  return bvh;
}

// Refit's bottom-up pass over the subtree of node `index`: every child slot gets its box (of its
// triangles' vertices in the leaves, as the builder's) and sphere (set_sphere, as build's).
// Returns the subtree's box. The depth is at most 64 (the builder's limit), so recursion is safe.
struct Box3 {
  glm::vec3 lo{INFINITY}, hi{-INFINITY};
};

Box3 refit_node(Bvh& bvh, std::uint32_t index) {
  Node& node = bvh.nodes[index];
  Box3 whole;
  for (int k = 0; k < node.child_count; ++k) {
    Box3 child;
    if (node.leaf_size[k] == 0) {
      child = refit_node(bvh, node.child[k]);
    } else {
      const LeafBlock block = bvh.leaf_at(node.child[k]);
      for (int l = 0; l < node.leaf_size[k]; ++l) {
        const lut::PackedTriangle t = block_triangle(block, l);
        for (const glm::vec3& v : {t.v0, t.v1, t.v2}) {
          child.lo = glm::min(child.lo, v);
          child.hi = glm::max(child.hi, v);
        }
      }
    }
    node.lo_x[k] = child.lo.x, node.lo_y[k] = child.lo.y, node.lo_z[k] = child.lo.z;
    node.hi_x[k] = child.hi.x, node.hi_y[k] = child.hi.y, node.hi_z[k] = child.hi.z;
    set_sphere(node, k, bvh);
    whole.lo = glm::min(whole.lo, child.lo);
    whole.hi = glm::max(whole.hi, child.hi);
  }
  return whole;
}

}  // namespace

Result<void> check_options(const BvhOptions& options) {
  if (options.branching != 2 && options.branching != 4) {
    return fail("bvh.branching: must be 2 or 4, got " + std::to_string(options.branching));
  }
  if (options.max_leaf_size < 1 || options.max_leaf_size > 8) {
    return fail("bvh.max_leaf_size: must be from 1 to 8, got " + std::to_string(options.max_leaf_size));
  }
  return {};
}

Result<Bvh> Bvh::build(const lut::TriangleSet& triangles, const BvhOptions& options, const ProgressCallback& progress) {
  return build_from(SetSource{triangles}, options, progress);
}

Result<Bvh> Bvh::build(const Scene& scene, const BvhOptions& options, const ProgressCallback& progress) {
  return build_from(SceneSource{scene}, options, progress);
}

Result<Bvh> Bvh::build(Scene&& scene, const BvhOptions& options, const ProgressCallback& progress) {
  return build_from(SceneSource{scene, &scene}, options, progress);
}

BvhBytes memory_bytes(const Bvh& bvh) {
  BvhBytes bytes;
  bytes.nodes = bvh.nodes.capacity() * sizeof(Node);
  bytes.leaves = bvh.leaf_floats.capacity() * sizeof(float);
  bytes.indices = (bvh.scene_triangle.capacity() + bvh.object.capacity()) * sizeof(std::uint32_t);
  return bytes;
}

void Bvh::refit(std::span<const glm::vec3> vertices) {
  EXAO_CHECK_EQ(vertices.size(), 3 * triangle_count());
  // The leaves keep their sidedness and cut-out bits (and the tree its objects); only the floats
  // move, with the spheres as TriangleSet::build computes them (the same floats as brute's).
  const auto refit_leaf = [&](std::uint32_t place) {
    const LeafBlock leaf = leaf_at(place);
    float largest = 0.0f;
    for (int l = 0; l < static_cast<int>(leaf.count); ++l) {
      const std::size_t t = scene_triangle[leaf.first + static_cast<std::uint32_t>(l)];
      const glm::vec3 &v0 = vertices[3 * t], &v1 = vertices[3 * t + 1], &v2 = vertices[3 * t + 2];
      glm::vec3 centre;
      float radius = 0.0f;
      lut::bounding_sphere(v0, v1, v2, centre, radius);
      put_lane(leaf_floats.data() + place + kLeafHeaderFloats, leaf.width, l, v0, v1, v2, centre, radius);
      for (const glm::vec3& v : {v0, v1, v2}) largest = std::max({largest, std::abs(v.x), std::abs(v.y), std::abs(v.z)});
    }
    return largest;
  };
  largest_coordinate = tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, nodes.size(), 256), 0.0f,
      [&](const tbb::blocked_range<std::size_t>& range, float largest) {
        for (std::size_t i = range.begin(); i != range.end(); ++i) {
          for (int k = 0; k < nodes[i].child_count; ++k) {
            if (nodes[i].leaf_size[k] != 0) largest = std::max(largest, refit_leaf(nodes[i].child[k]));
          }
        }
        return largest;
      },
      [](float x, float y) { return std::max(x, y); });
  refit_node(*this, 0);
}

}  // namespace exao::bvh
