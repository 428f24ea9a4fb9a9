#pragma once
// exao::ssao::abuffer_oit_ao: A-buffer AO with transparent receivers (seed 004, Bauer et al.
// 2013, Sec. III, Eq. 2-4, with the "separated" layer merging of their Fig. 4). Every fragment
// of a pixel's list, front to back up to the first opaque one, is a receiver: its AO is the
// horizon walk of ssao/abuffer_ao.h (occluders weighted by opacity) from its own point, once
// around its triangle's normal n (exterior, AO_e) and once around -n (interior, AO_i), mixed
// by W = alpha on a front face and 1 - alpha on a back face (Eq. 3-4; the thin-hull reading of
// their Fig. 5). The layers are then blended as transparency is: sum over k of
// T_k alpha_k AO_k with T_k = prod_{j<k} (1 - alpha_j), and what shows through the last layer
// (the background) is open. A fragment of opacity 0 is not there. The first fragment, when it
// is the G-buffer's triangle, is the G-buffer's receiver, so on opaque geometry (alpha = 1
// everywhere: W picks the hemisphere facing the eye) this is abuffer_ao bit for bit. Opacity is
// ssao/fragment_opacity.h's.

#include <vector>

#include "core/scene.h"
#include "ssao/abuffer_ao.h"

namespace exao::ssao {

/// AO per pixel, before any blur. `fragments` must be the view's size and from `scene`.
[[nodiscard]] std::vector<float> abuffer_oit_ao(const View& view, const FragmentBuffer& fragments, const Scene& scene,
                                                const Settings& settings, const HbaoOptions& options);

}  // namespace exao::ssao
