#include "ssao/list_compression.h"

#include <algorithm>
#include <cassert>
#include <string>

#include <tbb/parallel_for.h>

#include "ssao/fragment_opacity.h"

namespace exao::ssao {

Result<void> check(const ListCompression& options) {
  if (options.nodes < 1 || options.nodes > 64) return fail("list nodes: must be from 1 to 64, got " + std::to_string(options.nodes));
  return {};
}

FragmentBuffer compress_fragments(const FragmentBuffer& fragments, const View& view, const Scene& scene,
                                  const ListCompression& options) {
  assert(fragments.width == view.width && fragments.height == view.height);
  const std::size_t pixels = static_cast<std::size_t>(fragments.width) * static_cast<std::size_t>(fragments.height);
  const auto m = static_cast<std::size_t>(options.nodes);
  float far = 0.0f;
  for (const Fragment& f : fragments.fragments) far = std::max(far, f.depth);
  const double inverse_far = far > 0.0f ? 1.0 / static_cast<double>(far) : 0.0;

  // Per pixel, the kept fragments (at most m), then packed.
  std::vector<std::size_t> count(pixels, 0);
  std::vector<Fragment> kept(pixels * m);
  tbb::parallel_for(std::size_t{0}, pixels, [&](std::size_t p) {
    struct Node {
      Fragment fragment;
      double keep;  // a_alpha (1 - a_z): Eq. 5's criterion
    };
    std::vector<Node> a;
    a.reserve(m + 1);
    for (const Fragment& f : fragments.at(p)) {
      const double z = std::min(1.0, static_cast<double>(f.depth) * inverse_far);
      const Node node{f, static_cast<double>(fragment_opacity(scene, view, p, f)) * (1.0 - z)};
      // Insert at its depth: a[i]_z < f_z < a[i + 1]_z (after equal depths, as the list is ordered).
      const auto at = std::upper_bound(a.begin(), a.end(), f.depth, [](float d, const Node& n) { return d < n.fragment.depth; });
      a.insert(at, node);
      if (a.size() <= m) continue;
      // Eq. 5 over the candidates: the back half of the m + 1 nodes, or all of them.
      const std::size_t first = options.keep_front_half ? m / 2 : 0;
      std::size_t drop = first;
      for (std::size_t j = first; j < a.size(); ++j) {
        if (a[j].keep <= a[drop].keep) drop = j;  // ties: the farther one
      }
      a.erase(a.begin() + static_cast<std::ptrdiff_t>(drop));
    }
    count[p] = a.size();
    for (std::size_t k = 0; k < a.size(); ++k) kept[p * m + k] = a[k].fragment;
  });

  FragmentBuffer out;
  out.width = fragments.width;
  out.height = fragments.height;
  out.offset.assign(pixels + 1, 0);
  for (std::size_t p = 0; p < pixels; ++p) out.offset[p + 1] = out.offset[p] + count[p];
  out.fragments.resize(out.offset[pixels]);
  tbb::parallel_for(std::size_t{0}, pixels, [&](std::size_t p) {
    std::copy_n(kept.begin() + static_cast<std::ptrdiff_t>(p * m), count[p], out.fragments.begin() + static_cast<std::ptrdiff_t>(out.offset[p]));
  });
  return out;
}

}  // namespace exao::ssao
