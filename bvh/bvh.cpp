#include "bvh/bvh.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "core/check.h"

namespace exao::bvh {
namespace {

// The builder's own tree, pointer-linked in Embree's thread-local memory; flattened afterwards.
struct BuildNode {
  virtual ~BuildNode() = default;
  virtual bool is_leaf() const = 0;
};
struct BuildInner final : BuildNode {
  BuildNode* children[kMaxChildren] = {};
  RTCBounds bounds[kMaxChildren] = {};
  unsigned count = 0;
  bool is_leaf() const override { return false; }
};
struct BuildLeaf final : BuildNode {
  std::uint32_t triangles[8] = {};
  unsigned count = 0;
  RTCBounds bounds{};
  bool is_leaf() const override { return true; }
};

void* create_node(RTCThreadLocalAllocator alloc, unsigned count, void*) {
  void* memory = rtcThreadLocalAlloc(alloc, sizeof(BuildInner), 16);
  auto* node = new (memory) BuildInner;
  node->count = count;
  return node;
}

void set_children(void* node, void** children, unsigned count, void*) {
  auto* inner = static_cast<BuildInner*>(node);
  for (unsigned i = 0; i < count; ++i) inner->children[i] = static_cast<BuildNode*>(children[i]);
  inner->count = count;
}

void set_bounds(void* node, const RTCBounds** bounds, unsigned count, void*) {
  auto* inner = static_cast<BuildInner*>(node);
  for (unsigned i = 0; i < count; ++i) inner->bounds[i] = *bounds[i];
}

void* create_leaf(RTCThreadLocalAllocator alloc, const RTCBuildPrimitive* primitives, size_t count, void*) {
  void* memory = rtcThreadLocalAlloc(alloc, sizeof(BuildLeaf), 16);
  auto* leaf = new (memory) BuildLeaf;
  leaf->count = static_cast<unsigned>(count);
  for (size_t i = 0; i < count; ++i) leaf->triangles[i] = primitives[i].primID;
  return leaf;
}

struct Sphere {
  glm::dvec3 centre;
  double radius;
};

// A sphere around the box centre holding every triangle sphere of the subtree's triangles
// [first, last) (of `source`, triangle index_of(i)), tighter than the box's circumsphere, radius
// rounded up past the float centre: the region mask of this sphere must contain those of the
// triangles' spheres (lut/sphere_test.h, nesting).
template <class IndexOf>
Sphere enclosing_sphere(const RTCBounds& b, std::size_t first, std::size_t last, IndexOf index_of,
                        const lut::TriangleSet& source) {
  const glm::vec3 centre_f(0.5f * (b.lower_x + b.upper_x), 0.5f * (b.lower_y + b.upper_y), 0.5f * (b.lower_z + b.upper_z));
  const glm::dvec3 centre(centre_f);
  double radius = 0.0;
  for (std::size_t i = first; i < last; ++i) {
    const std::uint32_t t = index_of(i);
    radius = std::max(radius, glm::length(glm::dvec3(source.centre[t]) - centre) + double(source.radius[t]));
  }
  return {centre, static_cast<double>(std::nextafter(static_cast<float>(radius * (1.0 + 1e-6)), INFINITY))};
}

class Flattener {
 public:
  Flattener(const lut::TriangleSet& source, Bvh& bvh) : source_(source), bvh_(bvh) {}

  // Appends the subtree's triangles in leaf order; returns the slot data of the child.
  void fill_child(Node& parent, int slot, const BuildNode* child, const RTCBounds& bounds) {
    parent.lo_x[slot] = bounds.lower_x;
    parent.lo_y[slot] = bounds.lower_y;
    parent.lo_z[slot] = bounds.lower_z;
    parent.hi_x[slot] = bounds.upper_x;
    parent.hi_y[slot] = bounds.upper_y;
    parent.hi_z[slot] = bounds.upper_z;
    const std::size_t first_triangle = bvh_.scene_triangle.size();
    if (child->is_leaf()) {
      const auto* leaf = static_cast<const BuildLeaf*>(child);
      parent.child[slot] = static_cast<std::uint32_t>(first_triangle);
      parent.leaf_size[slot] = static_cast<std::uint8_t>(leaf->count);
      for (unsigned i = 0; i < leaf->count; ++i) bvh_.scene_triangle.push_back(leaf->triangles[i]);
    } else {
      parent.child[slot] = flatten(static_cast<const BuildInner*>(child));
      parent.leaf_size[slot] = 0;
    }
    const Sphere s = enclosing_sphere(bounds, first_triangle, bvh_.scene_triangle.size());
    parent.centre_x[slot] = static_cast<float>(s.centre.x);
    parent.centre_y[slot] = static_cast<float>(s.centre.y);
    parent.centre_z[slot] = static_cast<float>(s.centre.z);
    parent.radius[slot] = static_cast<float>(s.radius);
  }

  std::uint32_t flatten(const BuildInner* inner) {
    const auto index = static_cast<std::uint32_t>(bvh_.nodes.size());
    bvh_.nodes.emplace_back();
    Node node{};
    node.child_count = static_cast<std::uint8_t>(inner->count);
    for (unsigned k = 0; k < inner->count; ++k) fill_child(node, static_cast<int>(k), inner->children[k], inner->bounds[k]);
    bvh_.nodes[index] = node;
    return index;
  }

 private:
  Sphere enclosing_sphere(const RTCBounds& b, std::size_t first, std::size_t last) const {
    return bvh::enclosing_sphere(b, first, last, [&](std::size_t i) { return bvh_.scene_triangle[i]; }, source_);
  }

  const lut::TriangleSet& source_;
  Bvh& bvh_;
};

lut::TriangleSet permuted(const lut::TriangleSet& source, const std::vector<std::uint32_t>& order) {
  lut::TriangleSet out;
  const auto take = [&](auto& dst, const auto& src) {
    dst.resize(order.size());
    for (std::size_t i = 0; i < order.size(); ++i) dst[i] = src[order[i]];
  };
  take(out.v0, source.v0);
  take(out.v1, source.v1);
  take(out.v2, source.v2);
  take(out.two_sided, source.two_sided);
  take(out.object, source.object);
  take(out.centre, source.centre);
  take(out.radius, source.radius);
  return out;
}

// The leaf-order copies the kernels read (packed, blocks) from bvh.triangles.
void pack_leaves(Bvh& bvh);

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

Result<Bvh> Bvh::build(const lut::TriangleSet& triangles, const BvhOptions& options) {
  if (triangles.size() == 0) return fail("bvh: the scene has no triangles");
  if (auto ok = check_options(options); !ok) return std::unexpected(ok.error());

  RTCDevice device = rtcNewDevice(nullptr);
  if (!device) return fail("bvh: cannot create an Embree device");
  std::vector<RTCBuildPrimitive> primitives(triangles.size());
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    const glm::vec3 lo = glm::min(triangles.v0[t], glm::min(triangles.v1[t], triangles.v2[t]));
    const glm::vec3 hi = glm::max(triangles.v0[t], glm::max(triangles.v1[t], triangles.v2[t]));
    primitives[t] = RTCBuildPrimitive{lo.x, lo.y, lo.z, 0, hi.x, hi.y, hi.z, static_cast<unsigned>(t)};
  }
  RTCBVH embree_bvh = rtcNewBVH(device);
  RTCBuildArguments args = rtcDefaultBuildArguments();
  args.buildQuality = RTC_BUILD_QUALITY_HIGH;
  args.maxBranchingFactor = static_cast<unsigned>(options.branching);
  args.maxDepth = 64;
  args.minLeafSize = 1;
  args.maxLeafSize = static_cast<unsigned>(options.max_leaf_size);
  args.traversalCost = 1.0f;
  args.intersectionCost = 1.0f;
  args.bvh = embree_bvh;
  args.primitives = primitives.data();
  args.primitiveCount = primitives.size();
  args.primitiveArrayCapacity = primitives.size();
  args.createNode = create_node;
  args.setNodeChildren = set_children;
  args.setNodeBounds = set_bounds;
  args.createLeaf = create_leaf;
  const auto* root = static_cast<const BuildNode*>(rtcBuildBVH(&args));

  Bvh bvh;
  std::string error;
  if (!root) {
    error = "bvh: Embree's builder failed (" + std::to_string(static_cast<int>(rtcGetDeviceError(device))) + ")";
  } else {
    Flattener flattener(triangles, bvh);
    if (root->is_leaf()) {
      // A scene that fits one leaf still gets a root node, so traversal always starts at a node.
      bvh.nodes.emplace_back();
      Node node{};
      node.child_count = 1;
      // The builder gives a root leaf no bounds: use the union of the triangles' boxes.
      RTCBounds b{INFINITY, INFINITY, INFINITY, 0, -INFINITY, -INFINITY, -INFINITY, 0};
      for (std::size_t t = 0; t < triangles.size(); ++t) {
        b.lower_x = std::min(b.lower_x, primitives[t].lower_x);
        b.lower_y = std::min(b.lower_y, primitives[t].lower_y);
        b.lower_z = std::min(b.lower_z, primitives[t].lower_z);
        b.upper_x = std::max(b.upper_x, primitives[t].upper_x);
        b.upper_y = std::max(b.upper_y, primitives[t].upper_y);
        b.upper_z = std::max(b.upper_z, primitives[t].upper_z);
      }
      flattener.fill_child(node, 0, root, b);
      bvh.nodes[0] = node;
    } else {
      flattener.flatten(static_cast<const BuildInner*>(root));
    }
  }
  rtcReleaseBVH(embree_bvh);
  rtcReleaseDevice(device);
  if (!error.empty()) return fail(error);
  bvh.triangles = permuted(triangles, bvh.scene_triangle);
  pack_leaves(bvh);
  return bvh;
}

namespace {

void pack_leaves(Bvh& bvh) {
  bvh.packed.resize(bvh.triangles.size());
  bvh.largest_coordinate = 0.0f;
  bvh.blocks.clear();
  for (std::size_t t = 0; t < bvh.packed.size(); ++t) {
    bvh.packed[t] = bvh.triangles.packed(t);
    for (const glm::vec3& v : {bvh.packed[t].v0, bvh.packed[t].v1, bvh.packed[t].v2}) {
      bvh.largest_coordinate = std::max({bvh.largest_coordinate, std::abs(v.x), std::abs(v.y), std::abs(v.z)});
    }
  }
  // One block per leaf, in lanes.
  bvh.leaf_block.assign(bvh.packed.size(), 0);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (const Node& node : bvh.nodes) {
    for (int k = 0; k < node.child_count; ++k) {
      if (node.leaf_size[k] == 0) continue;
      LeafBlock block;
      for (int l = 0; l < LeafBlock::kLanes; ++l) {
        const bool used = l < node.leaf_size[k];
        const lut::PackedTriangle& t = bvh.packed[node.child[k] + (used ? l : 0)];
        const auto put = [&](float* lanes, float value) { lanes[l] = used ? value : nan; };
        put(block.v0x, t.v0.x), put(block.v0y, t.v0.y), put(block.v0z, t.v0.z);
        put(block.v1x, t.v1.x), put(block.v1y, t.v1.y), put(block.v1z, t.v1.z);
        put(block.v2x, t.v2.x), put(block.v2y, t.v2.y), put(block.v2z, t.v2.z);
        put(block.cx, t.centre.x), put(block.cy, t.centre.y), put(block.cz, t.centre.z);
        put(block.radius, t.radius);
        if (used && t.two_sided) block.two_sided |= 1u << l;
      }
      bvh.leaf_block[node.child[k]] = static_cast<std::uint32_t>(bvh.blocks.size());
      bvh.blocks.push_back(block);
    }
  }
}

}  // namespace

void Bvh::refit(const lut::TriangleSet& source) {
  EXAO_CHECK_EQ(source.size(), triangles.size());
  triangles = permuted(source, scene_triangle);
  pack_leaves(*this);
  // Nodes are stored parent before child (flatten's preorder), and a subtree's triangles are
  // contiguous in leaf order: so one pass from the last node up gives every child its box and
  // triangle range before its parent needs them.
  struct Extent {
    RTCBounds box;
    std::uint32_t first, last;
  };
  std::vector<Extent> extent(nodes.size());
  for (std::size_t i = nodes.size(); i-- > 0;) {
    Node& node = nodes[i];
    Extent whole{{INFINITY, INFINITY, INFINITY, 0, -INFINITY, -INFINITY, -INFINITY, 0}, UINT32_MAX, 0};
    for (int k = 0; k < node.child_count; ++k) {
      Extent child{{INFINITY, INFINITY, INFINITY, 0, -INFINITY, -INFINITY, -INFINITY, 0}, 0, 0};
      if (node.leaf_size[k] == 0) {
        child = extent[node.child[k]];
      } else {
        child.first = node.child[k];
        child.last = node.child[k] + node.leaf_size[k];
        for (std::uint32_t t = child.first; t < child.last; ++t) {
          for (const glm::vec3& v : {triangles.v0[t], triangles.v1[t], triangles.v2[t]}) {
            child.box.lower_x = std::min(child.box.lower_x, v.x), child.box.upper_x = std::max(child.box.upper_x, v.x);
            child.box.lower_y = std::min(child.box.lower_y, v.y), child.box.upper_y = std::max(child.box.upper_y, v.y);
            child.box.lower_z = std::min(child.box.lower_z, v.z), child.box.upper_z = std::max(child.box.upper_z, v.z);
          }
        }
      }
      node.lo_x[k] = child.box.lower_x, node.lo_y[k] = child.box.lower_y, node.lo_z[k] = child.box.lower_z;
      node.hi_x[k] = child.box.upper_x, node.hi_y[k] = child.box.upper_y, node.hi_z[k] = child.box.upper_z;
      const Sphere s = enclosing_sphere(child.box, child.first, child.last,
                                        [](std::size_t t) { return static_cast<std::uint32_t>(t); }, triangles);
      node.centre_x[k] = static_cast<float>(s.centre.x);
      node.centre_y[k] = static_cast<float>(s.centre.y);
      node.centre_z[k] = static_cast<float>(s.centre.z);
      node.radius[k] = static_cast<float>(s.radius);
      whole.box.lower_x = std::min(whole.box.lower_x, child.box.lower_x);
      whole.box.lower_y = std::min(whole.box.lower_y, child.box.lower_y);
      whole.box.lower_z = std::min(whole.box.lower_z, child.box.lower_z);
      whole.box.upper_x = std::max(whole.box.upper_x, child.box.upper_x);
      whole.box.upper_y = std::max(whole.box.upper_y, child.box.upper_y);
      whole.box.upper_z = std::max(whole.box.upper_z, child.box.upper_z);
      whole.first = std::min(whole.first, child.first);
      whole.last = std::max(whole.last, child.last);
    }
    extent[i] = whole;
  }
}

}  // namespace exao::bvh
