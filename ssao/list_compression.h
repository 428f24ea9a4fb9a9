#pragma once
// exao::ssao::compress_fragments: seed 004's fixed-size list compression (Bauer et al. 2013,
// Sec. III-B; its variants measured in Sec. V-A, Fig. 6). Each pixel's fragments are inserted,
// nearest first as the resolve pass has them sorted, into an array of m nodes kept in depth
// order; once more than m have been inserted, the node j with the least a[j]_alpha (1 - a[j]_z)
// is dropped (their Eq. 5): opaque and near fragments stay, transparent and far ones go. z is
// the normalised depth in [0, 1] (the view depth over the farthest fragment of the buffer, the
// scene's far plane), alpha the fragment's opacity (ssao/fragment_opacity.h). With
// `keep_front_half` the search runs over the back half of the array only (their column C, the
// variant Sec. V-B uses: "the top four layers are favored"), so the first m/2 fragments of a
// list always stay. On opaque geometry (alpha = 1 everywhere) Eq. 5 drops the farthest node:
// the list becomes its m nearest fragments. A list of at most m fragments is left as it is.
// Ties in Eq. 5 drop the farther node.

#include <vector>

#include "core/error.h"
#include "core/scene.h"
#include "ssao/fragment_buffer.h"
#include "ssao/view.h"

namespace exao::ssao {

struct ListCompression {
  int nodes = 4;                // m, 1 .. 64: seed 004 stores four nodes in an RGB32UI texel
  bool keep_front_half = true;  // search Eq. 5 over the back half only (their Sec. V-A, column C)
};

[[nodiscard]] Result<void> check(const ListCompression& options);

/// The A-buffer with every list compressed to at most options.nodes fragments, still nearest
/// first. `view` and `scene` are those of `fragments` (for the opacities).
[[nodiscard]] FragmentBuffer compress_fragments(const FragmentBuffer& fragments, const View& view, const Scene& scene,
                                                const ListCompression& options);

}  // namespace exao::ssao
