#include "bvh/sah_builder.h"

#include "core/huge_pages.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <memory>
#include <limits>
#include <string>

#include <emmintrin.h>

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>
#include <tbb/task_group.h>

namespace exao::bvh {
namespace {

constexpr int kBins = 32;  // Embree's NUM_OBJECT_BINS
// Traversal's stack holds 64 levels (bvh/traverse.h, kStackSize). Below kSahDepth the builder
// splits by count alone (halves), as Embree's "large leaf" does near its depth limit.
constexpr int kMaxDepth = 64;
constexpr int kSahDepth = 56;
constexpr std::size_t kParallelSubtree = 4096;   // smaller subtrees are one task
constexpr std::uint32_t kParallelFlatten = 1024;  // nodes: smaller subtrees are flattened by one task
constexpr std::size_t kParallelRange = 1 << 17;  // larger ranges are binned and bounded in parallel
constexpr std::size_t kGrain = 1 << 15;
constexpr float kInf = std::numeric_limits<float>::infinity();

struct Box {
  float lo[3] = {kInf, kInf, kInf};
  float hi[3] = {-kInf, -kInf, -kInf};

  void extend(const float* l, const float* h) {
    for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], l[a]), hi[a] = std::max(hi[a], h[a]);
  }
  void extend(const Box& b) { extend(b.lo, b.hi); }
  [[nodiscard]] float half_area() const {
    const float dx = hi[0] - lo[0], dy = hi[1] - lo[1], dz = hi[2] - lo[2];
    return dx * (dy + dz) + dy * dz;
  }
};

const float* lo_of(const BuildPrimitive& p) { return &p.lo_x; }
const float* hi_of(const BuildPrimitive& p) { return &p.hi_x; }
// Twice the centroid (lo + hi), as Embree bins it: one add, no rounding to halve.
void centroid2(const BuildPrimitive& p, float* c) {
  c[0] = p.lo_x + p.hi_x, c[1] = p.lo_y + p.hi_y, c[2] = p.lo_z + p.hi_z;
}

// A contiguous run of primitives with the box of their boxes and of their (doubled) centroids.
struct Range {
  std::size_t begin = 0, end = 0;
  Box geometry, centroids;
  [[nodiscard]] std::size_t size() const { return end - begin; }
};

struct Bounds2 {
  Box geometry, centroids;
  void merge(const Bounds2& o) { geometry.extend(o.geometry), centroids.extend(o.centroids); }
};

struct Bins {
  Box box[3][kBins];
  std::uint32_t count[3][kBins] = {};
  void merge(const Bins& o) {
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < kBins; ++b) box[a][b].extend(o.box[a][b]), count[a][b] += o.count[a][b];
  }
};

// Which bin of each axis a primitive's centroid falls in.
struct BinMapping {
  float lo[3] = {}, scale[3] = {};
  explicit BinMapping(const Box& centroids) {
    for (int a = 0; a < 3; ++a) {
      lo[a] = centroids.lo[a];
      const float extent = centroids.hi[a] - centroids.lo[a];
      scale[a] = extent > 0.0f ? 0.99f * kBins / extent : 0.0f;
    }
  }
  [[nodiscard]] int bin(float c, int axis) const {
    const int b = static_cast<int>((c - lo[axis]) * scale[axis]);
    return std::clamp(b, 0, kBins - 1);
  }
};

struct Split {
  int axis = -1;  // -1: no split by the SAH (every centroid in one bin): halve by count
  int position = 0;  // left: bins below it; or, `sorted`, the first `position` along the axis
  float sah = kInf;  // sum over both sides of half area x triangles
  bool sorted = false;
};

// Small ranges are split by a full sweep over the sorted centroids rather than by 32 bins:
// cheaper there (a range of a few triangles would fill and sweep 96 bins) and no worse a split.
constexpr std::size_t kSortedSplit = 24;

bool centroid_less(const BuildPrimitive& x, const BuildPrimitive& y, int axis) {
  const float cx = lo_of(x)[axis] + hi_of(x)[axis], cy = lo_of(y)[axis] + hi_of(y)[axis];
  return cx < cy || (cx == cy && x.index < y.index);
}

class Builder {
 public:
  Builder(BuildPrimitives& prims, const BvhOptions& options, const SahCosts& costs,
          const ProgressCallback& progress)
      : prims_(prims), options_(options), costs_(costs), progress_(progress, prims.size()) {}

  // A node before flattening: only what the build decides (no spheres), 160 bytes against a
  // Node's 184 plus the links; a million of them at 8M triangles, written once each.
  struct TmpNode {
    float lo_x[kMaxChildren] = {}, lo_y[kMaxChildren] = {}, lo_z[kMaxChildren] = {};
    float hi_x[kMaxChildren] = {}, hi_y[kMaxChildren] = {}, hi_z[kMaxChildren] = {};
    std::uint32_t first[kMaxChildren] = {};   // a leaf slot's first triangle
    TmpNode* child[kMaxChildren] = {};         // an internal slot's node
    std::uint8_t leaf_size[kMaxChildren] = {};  // 0 for an internal slot
    std::uint8_t child_count = 0;
    std::uint32_t subtree_nodes = 1;  // this node and every node below it
  };

  Range whole() { return bounded(0, prims_.size()); }

  // Decides `r`: a leaf in slot `slot` of `parent`, or a node of its own below that slot.
  void build(const Range& r, int depth, TmpNode& parent, int slot) {
    TmpNode& p = parent;
    p.lo_x[slot] = r.geometry.lo[0], p.lo_y[slot] = r.geometry.lo[1], p.lo_z[slot] = r.geometry.lo[2];
    p.hi_x[slot] = r.geometry.hi[0], p.hi_y[slot] = r.geometry.hi[1], p.hi_z[slot] = r.geometry.hi[2];
    const std::size_t n = r.size();
    const bool by_count = depth >= kSahDepth;
    const Split split = n > 1 && !by_count ? find_split(r) : Split{};
    const float leaf_sah = costs_.intersection * r.geometry.half_area() * static_cast<float>(n);
    const float split_sah = costs_.traversal * r.geometry.half_area() + costs_.intersection * split.sah;
    if (n <= 1 || (n <= static_cast<std::size_t>(options_.max_leaf_size) && leaf_sah <= split_sah)) {
      p.first[slot] = static_cast<std::uint32_t>(r.begin);
      p.leaf_size[slot] = static_cast<std::uint8_t>(n);
      progress_.add(n);
      return;
    }
    if (depth >= kMaxDepth - 1) {
      too_deep_ = true;
      return;
    }
    TmpNode& node = storage_.local().make();
    parent.child[slot] = &node;
    p.leaf_size[slot] = 0;

    Range children[kMaxChildren];
    apply(r, split, children[0], children[1]);
    int count = 2;
    while (count < options_.branching) {
      // Split the child of largest area (of most triangles, when splitting by count).
      int best = -1;
      float best_key = -kInf;
      for (int i = 0; i < count; ++i) {
        if (children[i].size() <= 1) continue;
        const float key = by_count ? static_cast<float>(children[i].size()) : children[i].geometry.half_area();
        if (key > best_key) best = i, best_key = key;
      }
      if (best < 0) break;
      const Range parent_range = children[best];
      apply(parent_range, by_count ? Split{} : find_split(parent_range), children[best], children[count]);
      ++count;
    }
    node.child_count = static_cast<std::uint8_t>(count);
    if (n > kParallelSubtree) {
      tbb::task_group group;
      for (int k = 0; k < count; ++k) group.run([&, k] { build(children[k], depth + 1, node, k); });
      group.wait();
    } else {
      for (int k = 0; k < count; ++k) build(children[k], depth + 1, node, k);
    }
    for (int k = 0; k < count; ++k)
      if (node.child[k] != nullptr) node.subtree_nodes += node.child[k]->subtree_nodes;
  }

  [[nodiscard]] bool too_deep() const { return too_deep_; }

 private:
  Range bounded(std::size_t begin, std::size_t end) const {
    // SSE, as the binning: a primitive's lo and hi are one load each (lane 3 carried and
    // ignored), its doubled centroid one add; the same floats as centroid2 and Box::extend.
    const auto over = [&](const tbb::blocked_range<std::size_t>& range, Bounds2 b) {
      __m128 lo = _mm_set1_ps(kInf), hi = _mm_set1_ps(-kInf), c_lo = lo, c_hi = hi;
      for (std::size_t i = range.begin(); i != range.end(); ++i) {
        const __m128 l = _mm_loadu_ps(&prims_[i].lo_x), h = _mm_loadu_ps(&prims_[i].hi_x);
        const __m128 c = _mm_add_ps(l, h);
        // (new, old): an unordered pair keeps the old value, as std::min(old, new) does.
        lo = _mm_min_ps(l, lo), hi = _mm_max_ps(h, hi);
        c_lo = _mm_min_ps(c, c_lo), c_hi = _mm_max_ps(c, c_hi);
      }
      alignas(16) float l[4], h[4], cl[4], ch[4];
      _mm_store_ps(l, lo), _mm_store_ps(h, hi), _mm_store_ps(cl, c_lo), _mm_store_ps(ch, c_hi);
      b.geometry.extend(l, h);
      b.centroids.extend(cl, ch);
      return b;
    };
    Bounds2 b;
    if (end - begin > kParallelRange) {
      b = tbb::parallel_reduce(tbb::blocked_range<std::size_t>(begin, end, kGrain), Bounds2{}, over,
                               [](Bounds2 x, const Bounds2& y) { x.merge(y); return x; });
    } else {
      b = over(tbb::blocked_range<std::size_t>(begin, end), Bounds2{});
    }
    return {begin, end, b.geometry, b.centroids};
  }

  Split find_split(const Range& r) const {
    if (r.size() <= kSortedSplit) return find_sorted_split(r);
    const BinMapping mapping(r.centroids);
    if (mapping.scale[0] == 0.0f && mapping.scale[1] == 0.0f && mapping.scale[2] == 0.0f) return {};
    // SSE: a primitive's lo and hi are one load each (lane 3, the index, is carried and
    // ignored); the same floats and the same bins as BinMapping::bin, in a third of the time.
    const __m128 origin = _mm_setr_ps(mapping.lo[0], mapping.lo[1], mapping.lo[2], 0.0f);
    const __m128 scale = _mm_setr_ps(mapping.scale[0], mapping.scale[1], mapping.scale[2], 0.0f);
    const auto over = [&](const tbb::blocked_range<std::size_t>& range, Bins& bins) {
      __m128 lo[3][kBins], hi[3][kBins];
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < kBins; ++b) lo[a][b] = _mm_set1_ps(kInf), hi[a][b] = _mm_set1_ps(-kInf);
      for (std::size_t i = range.begin(); i != range.end(); ++i) {
        const BuildPrimitive& p = prims_[i];
        const __m128 l = _mm_loadu_ps(&p.lo_x), h = _mm_loadu_ps(&p.hi_x);
        alignas(16) std::int32_t bin[4];
        _mm_store_si128(reinterpret_cast<__m128i*>(bin), _mm_cvttps_epi32(_mm_mul_ps(_mm_sub_ps(_mm_add_ps(l, h), origin), scale)));
        for (int a = 0; a < 3; ++a) {
          const int b = std::clamp(bin[a], 0, kBins - 1);
          lo[a][b] = _mm_min_ps(lo[a][b], l);
          hi[a][b] = _mm_max_ps(hi[a][b], h);
          ++bins.count[a][b];
        }
      }
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < kBins; ++b) {
          alignas(16) float l[4], h[4];
          _mm_store_ps(l, lo[a][b]);
          _mm_store_ps(h, hi[a][b]);
          bins.box[a][b].extend(l, h);
        }
    };
    Bins bins;
    if (r.size() > kParallelRange) {
      tbb::enumerable_thread_specific<Bins> local;
      tbb::parallel_for(tbb::blocked_range<std::size_t>(r.begin, r.end, kGrain),
                        [&](const tbb::blocked_range<std::size_t>& range) { over(range, local.local()); });
      for (const Bins& b : local) bins.merge(b);
    } else {
      over(tbb::blocked_range<std::size_t>(r.begin, r.end), bins);
    }
    Split best;
    for (int a = 0; a < 3; ++a) {
      if (mapping.scale[a] == 0.0f) continue;
      // Right-to-left sweep: the cost of every right side; then left to right.
      float right_sah[kBins] = {};
      Box right;
      std::uint32_t right_count = 0;
      for (int b = kBins - 1; b > 0; --b) {
        right.extend(bins.box[a][b]);
        right_count += bins.count[a][b];
        right_sah[b] = right_count ? right.half_area() * static_cast<float>(right_count) : kInf;
      }
      Box left;
      std::uint32_t left_count = 0;
      for (int b = 1; b < kBins; ++b) {
        left.extend(bins.box[a][b - 1]);
        left_count += bins.count[a][b - 1];
        if (left_count == 0 || left_count == r.size()) continue;
        const float sah = left.half_area() * static_cast<float>(left_count) + right_sah[b];
        if (sah < best.sah) best = {a, b, sah};
      }
    }
    return best;
  }

  Split find_sorted_split(const Range& r) const {
    const std::size_t n = r.size();
    BuildPrimitive sorted[kSortedSplit];
    Split best;
    for (int a = 0; a < 3; ++a) {
      if (!(r.centroids.hi[a] > r.centroids.lo[a])) continue;
      std::copy(prims_.begin() + static_cast<std::ptrdiff_t>(r.begin), prims_.begin() + static_cast<std::ptrdiff_t>(r.end), sorted);
      std::sort(sorted, sorted + n, [a](const BuildPrimitive& x, const BuildPrimitive& y) { return centroid_less(x, y, a); });
      float right_sah[kSortedSplit] = {};
      Box right;
      for (std::size_t i = n - 1; i > 0; --i) {
        right.extend(lo_of(sorted[i]), hi_of(sorted[i]));
        right_sah[i] = right.half_area() * static_cast<float>(n - i);
      }
      Box left;
      for (std::size_t i = 1; i < n; ++i) {
        left.extend(lo_of(sorted[i - 1]), hi_of(sorted[i - 1]));
        const float sah = left.half_area() * static_cast<float>(i) + right_sah[i];
        if (sah < best.sah) best = {a, static_cast<int>(i), sah, true};
      }
    }
    return best;
  }

  // Partitions r by the split (bins below its position to the left, or the first `position`
  // along the axis), or halves it by count.
  void apply(const Range& r, const Split& split, Range& left, Range& right) {
    std::size_t middle = r.begin + r.size() / 2;
    if (split.sorted) {
      const int axis = split.axis;
      std::sort(prims_.begin() + static_cast<std::ptrdiff_t>(r.begin), prims_.begin() + static_cast<std::ptrdiff_t>(r.end),
                [axis](const BuildPrimitive& x, const BuildPrimitive& y) { return centroid_less(x, y, axis); });
      middle = r.begin + static_cast<std::size_t>(split.position);
    } else if (split.axis >= 0) {
      const BinMapping mapping(r.centroids);
      const int axis = split.axis;
      const auto it = std::partition(prims_.begin() + static_cast<std::ptrdiff_t>(r.begin),
                                     prims_.begin() + static_cast<std::ptrdiff_t>(r.end), [&](const BuildPrimitive& p) {
                                       float c[3];
                                       centroid2(p, c);
                                       return mapping.bin(c[axis], axis) < split.position;
                                     });
      middle = static_cast<std::size_t>(it - prims_.begin());
    }
    left = bounded(r.begin, middle);
    right = bounded(middle, r.end);
  }

  BuildPrimitives& prims_;
  const BvhOptions& options_;
  SahCosts costs_;
  ProgressCounter progress_;
  // The nodes before flattening, in chunks per thread: a deque's 512-byte blocks were a malloc
  // every second node, a million at 8M triangles.
  struct NodeArena {
    static constexpr std::size_t kChunk = 4096;
    std::vector<std::unique_ptr<TmpNode[]>> chunks;
    std::size_t used = kChunk;
    TmpNode& make() {
      if (used == kChunk) chunks.push_back(std::make_unique<TmpNode[]>(kChunk)), used = 0;
      return chunks.back()[used++];
    }
  };
  tbb::enumerable_thread_specific<NodeArena> storage_;
  std::atomic<bool> too_deep_{false};
};

// Node `t` as the tree keeps it, its internal children at `places`; spheres and unused slots zero.
Node node_of(const Builder::TmpNode& t, const std::uint32_t* places) {
  Node node{};
  for (int k = 0; k < t.child_count; ++k) {
    node.lo_x[k] = t.lo_x[k], node.lo_y[k] = t.lo_y[k], node.lo_z[k] = t.lo_z[k];
    node.hi_x[k] = t.hi_x[k], node.hi_y[k] = t.hi_y[k], node.hi_z[k] = t.hi_z[k];
    node.leaf_size[k] = t.leaf_size[k];
    node.child[k] = t.leaf_size[k] != 0 ? t.first[k] : places[k];
  }
  node.child_count = t.child_count;
  return node;
}

// Writes the subtree of `t` from out.nodes[index] on: depth first, a node before its children,
// children in slot order (the layout Embree's tree was flattened into before, so that a
// subtree's nodes sit together). Each child's place follows from its elder siblings' subtree
// sizes, so large subtrees are written in parallel.
void flatten(const Builder::TmpNode& t, std::uint32_t index, Topology& out) {
  std::uint32_t places[kMaxChildren] = {};
  std::uint32_t next = index + 1;
  for (int k = 0; k < t.child_count; ++k) {
    if (t.leaf_size[k] != 0) continue;
    places[k] = next;
    next += t.child[k]->subtree_nodes;
  }
  out.nodes[index] = node_of(t, places);
  const auto internal = [&](int k) { return t.leaf_size[k] == 0; };
  if (t.subtree_nodes < kParallelFlatten) {
    for (int k = 0; k < t.child_count; ++k)
      if (internal(k)) flatten(*t.child[k], places[k], out);
    return;
  }
  tbb::task_group group;
  for (int k = 0; k < t.child_count; ++k)
    if (internal(k)) group.run([&, k] { flatten(*t.child[k], places[k], out); });
  group.wait();
}

}  // namespace

Result<Topology> build_topology(BuildPrimitives& primitives, const BvhOptions& options, const SahCosts& costs,
                                const ProgressCallback& progress) {
  if (primitives.empty()) return fail("bvh: the scene has no triangles");
  if (auto ok = check_options(options); !ok) return std::unexpected(ok.error());
  Builder builder(primitives, options, costs, progress);
  // A one-slot node above the root: the root is its child, or (a scene that fits one leaf) the
  // root is that node itself, so traversal always starts at a node.
  Builder::TmpNode top;
  top.child_count = 1;
  builder.build(builder.whole(), 0, top, 0);
  if (builder.too_deep()) {
    return fail("bvh: more than " + std::to_string(kMaxDepth) + " levels: too many triangles share one centroid");
  }
  Topology out;
  reserve_huge(out.order, primitives.size());
  out.order.resize(primitives.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, primitives.size(), kGrain), [&](const tbb::blocked_range<std::size_t>& range) {
    for (std::size_t i = range.begin(); i != range.end(); ++i) out.order[i] = primitives[i].index;
  });
  // Freed before the nodes are written, so that the kernel can give their pages to the nodes:
  // a page touched for the first time costs most (docs/scale.md, "This machine's fresh memory").
  BuildPrimitives().swap(primitives);
  if (top.leaf_size[0] != 0) {
    out.nodes.push_back(node_of(top, nullptr));
  } else {
    reserve_huge(out.nodes, top.child[0]->subtree_nodes);
    out.nodes.resize(top.child[0]->subtree_nodes);  // unwritten until flatten writes each node
    flatten(*top.child[0], 0, out);
  }
  return out;
}

}  // namespace exao::bvh
