#include "bvh/bvh.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include "bvh/sah_builder.h"
#include "core/check.h"

namespace exao::bvh {
namespace {

constexpr std::size_t kGrain = 1 << 14;

// Where the triangles come from: a TriangleSet (spheres already computed) or a Scene (computed
// here by the same function, so the floats are the same).
struct SetSource {
  const lut::TriangleSet& set;
  [[nodiscard]] std::size_t size() const { return set.size(); }
  [[nodiscard]] glm::vec3 vertex(std::size_t t, int k) const { return k == 0 ? set.v0[t] : k == 1 ? set.v1[t] : set.v2[t]; }
  [[nodiscard]] lut::PackedTriangle packed(std::size_t t) const { return set.packed(t); }
  [[nodiscard]] std::shared_ptr<const Cutouts> cutouts() const { return set.cutouts; }
  void release() const {}
};

struct SceneSource {
  const Scene& scene;
  Scene* owned = nullptr;  // the caller's scene to free once the packed copy is made, or null
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
  [[nodiscard]] std::shared_ptr<const Cutouts> cutouts() const {
    return scene.cutouts && scene.cutouts->any() ? scene.cutouts : nullptr;
  }
  // The packed triangles hold every float the tree needs from here on.
  void release() const {
    if (owned) *owned = Scene{};
  }
};

// A sphere around the box centre holding every triangle sphere of the subtree (tighter than
// the box's circumsphere), radius rounded up past the float centre: the region mask of this
// sphere must contain those of the triangles' spheres (lut/sphere_test.h, nesting).
void set_sphere(Node& node, int slot, const Bvh& bvh, std::uint32_t first, std::uint32_t last) {
  const glm::vec3 centre_f(0.5f * (node.lo_x[slot] + node.hi_x[slot]), 0.5f * (node.lo_y[slot] + node.hi_y[slot]),
                           0.5f * (node.lo_z[slot] + node.hi_z[slot]));
  const glm::dvec3 centre(centre_f);
  double radius = 0.0;
  for (std::uint32_t i = first; i < last; ++i) {
    const lut::PackedTriangle& t = bvh.packed[i];
    radius = std::max(radius, glm::length(glm::dvec3(t.centre) - centre) + double(t.radius));
  }
  node.centre_x[slot] = centre_f.x;
  node.centre_y[slot] = centre_f.y;
  node.centre_z[slot] = centre_f.z;
  node.radius[slot] = std::nextafter(static_cast<float>(radius * (1.0 + 1e-6)), INFINITY);
}

LeafBlock make_block(const Bvh& bvh, std::uint32_t first, int size) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  LeafBlock block;
  for (int l = 0; l < LeafBlock::kLanes; ++l) {
    const bool used = l < size;
    const lut::PackedTriangle& t = bvh.packed[first + static_cast<std::uint32_t>(used ? l : 0)];
    const auto put = [&](float* lanes, float value) { lanes[l] = used ? value : nan; };
    put(block.v0x, t.v0.x), put(block.v0y, t.v0.y), put(block.v0z, t.v0.z);
    put(block.v1x, t.v1.x), put(block.v1y, t.v1.y), put(block.v1z, t.v1.z);
    put(block.v2x, t.v2.x), put(block.v2y, t.v2.y), put(block.v2z, t.v2.z);
    put(block.cx, t.centre.x), put(block.cy, t.centre.y), put(block.cz, t.centre.z);
    put(block.radius, t.radius);
    if (used && t.two_sided) block.two_sided |= 1u << l;
    if (used && t.cutout) block.cutout |= 1u << l;
  }
  return block;
}

template <class Source>
Result<Bvh> build_from(const Source& source, const BvhOptions& options, const ProgressCallback& progress) {
  const std::size_t n = source.size();
  if (n == 0) return fail("bvh: the scene has no triangles");
  if (auto ok = check_options(options); !ok) return std::unexpected(ok.error());
  // Progress: the topology reports n (triangles placed in leaves), the packing n more.
  const ProgressCallback topology_progress =
      progress ? ProgressCallback([&](std::size_t done, std::size_t) { progress(done, 2 * n); }) : ProgressCallback();

  Result<Topology> topology;
  {
    std::vector<BuildPrimitive> primitives(n);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, kGrain), [&](const tbb::blocked_range<std::size_t>& range) {
      for (std::size_t t = range.begin(); t != range.end(); ++t) {
        const glm::vec3 a = source.vertex(t, 0), b = source.vertex(t, 1), c = source.vertex(t, 2);
        const glm::vec3 lo = glm::min(a, glm::min(b, c)), hi = glm::max(a, glm::max(b, c));
        primitives[t] = {lo.x, lo.y, lo.z, static_cast<std::uint32_t>(t), hi.x, hi.y, hi.z, 0.0f};
      }
    });
    topology = build_topology(primitives, options, {}, topology_progress);
  }  // the primitives (32 bytes a triangle) go before the packed triangles come
  if (!topology) return std::unexpected(topology.error());

  Bvh bvh;
  bvh.cutouts = source.cutouts();
  bvh.nodes = std::move(topology->nodes);
  bvh.scene_triangle = std::move(topology->order);
  bvh.packed.resize(n);
  std::atomic<std::size_t> packed_count{0};
  bvh.largest_coordinate = tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, n, kGrain), 0.0f,
      [&](const tbb::blocked_range<std::size_t>& range, float largest) {
        for (std::size_t i = range.begin(); i != range.end(); ++i) {
          const lut::PackedTriangle p = source.packed(bvh.scene_triangle[i]);
          bvh.packed[i] = p;
          for (const glm::vec3& v : {p.v0, p.v1, p.v2}) largest = std::max({largest, std::abs(v.x), std::abs(v.y), std::abs(v.z)});
        }
        if (progress) progress(n + (packed_count += range.size()), 2 * n);
        return largest;
      },
      [](float x, float y) { return std::max(x, y); });
  source.release();

  // The node spheres, and one block per leaf in node order, then slot order.
  const std::vector<Topology::SlotRange>& ranges = topology->ranges;
  std::vector<std::uint32_t> first_block(bvh.nodes.size() + 1, 0);
  for (std::size_t i = 0; i < bvh.nodes.size(); ++i) {
    const Node& node = bvh.nodes[i];
    std::uint32_t leaves = 0;
    for (int k = 0; k < node.child_count; ++k) leaves += node.leaf_size[k] != 0;
    first_block[i + 1] = first_block[i] + leaves;
  }
  bvh.blocks.resize(first_block.back());
  bvh.leaf_block.assign(n, 0);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, bvh.nodes.size(), 256), [&](const tbb::blocked_range<std::size_t>& range) {
    for (std::size_t i = range.begin(); i != range.end(); ++i) {
      Node& node = bvh.nodes[i];
      std::uint32_t block = first_block[i];
      for (int k = 0; k < node.child_count; ++k) {
        set_sphere(node, k, bvh, ranges[i].first[k], ranges[i].last[k]);
        if (node.leaf_size[k] == 0) continue;
        bvh.leaf_block[node.child[k]] = block;
        bvh.blocks[block++] = make_block(bvh, node.child[k], node.leaf_size[k]);
      }
    }
  });
  return bvh;
}

// Refit's bottom-up pass over the subtree of node `index`: every child slot gets its box (of its
// packed triangles' vertices, as the builder's) and sphere (set_sphere, as build's), every leaf
// its block. Returns the subtree's box and its range [first, last) of packed triangles. The
// depth is at most 64 (the builder's limit), so recursion is safe.
struct Extent {
  glm::vec3 lo{INFINITY}, hi{-INFINITY};
  std::uint32_t first = UINT32_MAX, last = 0;
};

Extent refit_node(Bvh& bvh, std::uint32_t index) {
  Node& node = bvh.nodes[index];
  Extent whole;
  for (int k = 0; k < node.child_count; ++k) {
    Extent child;
    if (node.leaf_size[k] == 0) {
      child = refit_node(bvh, node.child[k]);
    } else {
      child.first = node.child[k];
      child.last = node.child[k] + node.leaf_size[k];
      for (std::uint32_t t = child.first; t < child.last; ++t) {
        for (const glm::vec3& v : {bvh.packed[t].v0, bvh.packed[t].v1, bvh.packed[t].v2}) {
          child.lo = glm::min(child.lo, v);
          child.hi = glm::max(child.hi, v);
        }
      }
      bvh.blocks[bvh.leaf_block[node.child[k]]] = make_block(bvh, node.child[k], node.leaf_size[k]);
    }
    node.lo_x[k] = child.lo.x, node.lo_y[k] = child.lo.y, node.lo_z[k] = child.lo.z;
    node.hi_x[k] = child.hi.x, node.hi_y[k] = child.hi.y, node.hi_z[k] = child.hi.z;
    set_sphere(node, k, bvh, child.first, child.last);
    whole.lo = glm::min(whole.lo, child.lo);
    whole.hi = glm::max(whole.hi, child.hi);
    whole.first = std::min(whole.first, child.first);
    whole.last = std::max(whole.last, child.last);
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
  bytes.blocks = bvh.blocks.capacity() * sizeof(LeafBlock);
  bytes.packed = bvh.packed.capacity() * sizeof(lut::PackedTriangle);
  bytes.indices = (bvh.scene_triangle.capacity() + bvh.leaf_block.capacity()) * sizeof(std::uint32_t);
  return bytes;
}

void Bvh::refit(std::span<const glm::vec3> vertices) {
  EXAO_CHECK_EQ(vertices.size(), 3 * packed.size());
  // The packed triangles keep their sidedness, cut-out flag and object; only the floats move,
  // with the spheres as TriangleSet::build computes them (the same floats as brute's).
  largest_coordinate = tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, packed.size(), kGrain), 0.0f,
      [&](const tbb::blocked_range<std::size_t>& range, float largest) {
        for (std::size_t i = range.begin(); i != range.end(); ++i) {
          lut::PackedTriangle& p = packed[i];
          const std::size_t t = scene_triangle[i];
          p.v0 = vertices[3 * t];
          p.v1 = vertices[3 * t + 1];
          p.v2 = vertices[3 * t + 2];
          lut::bounding_sphere(p.v0, p.v1, p.v2, p.centre, p.radius);
          for (const glm::vec3& v : {p.v0, p.v1, p.v2}) largest = std::max({largest, std::abs(v.x), std::abs(v.y), std::abs(v.z)});
        }
        return largest;
      },
      [](float x, float y) { return std::max(x, y); });
  refit_node(*this, 0);
}

}  // namespace exao::bvh
