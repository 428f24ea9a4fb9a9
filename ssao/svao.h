#pragma once
// exao::ssao: the stenciled two-phase VAO of seed 001. Phase 1 is ssao::vao on the depth buffer,
// which flags every sample whose surface lies in front of the constant area and marks, in the
// stochastic depth mask, the pixel that sample reads. Phase 2 revisits only the flagged pixels:
//  * SD-SVAO (their Sec. 3.9): a stochastic depth map drawn for the marked pixels only (the
//    stencil), and each flagged sample's unoccupied length is the least over the first layer
//    and every stochastic depth of its pixel, a_i = min(a_i1, ..., a_ij) (Sec. 3.6-3.7).
//  * RT-SVAO in the paper's form (Sec. 3.8, with Sec. 3.6's rays): every flagged sample casts a
//    ray along its own column, from the far end of the halo's falloff area (1 + tau + the
//    column's length in front of the receiver, where a surface stops mattering) back to the
//    end of the hemisphere part (z_lo), and its unoccupied length is the least over the first
//    layer and every surface the ray crosses, a_i = min(a_i1, ..., a_ij) (their Fig. 6).
//    Unflagged samples keep phase 1's value. The rays come through a callback (SegmentHits),
//    so this module needs no ray caster.
//  * RT-SVAO as exao had it first ("rtsvao"): rays for the flagged pixels, but exao's own, a
//    flagged pixel taking the exact AO of its receiver (the caller computes it for those pixels
//    only), an unflagged one keeping phase 1's value, so its error is VAO's error where
//    nothing was flagged. Not the paper's estimator: kept as a row of its own.

#include <functional>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "ssao/stochastic_depth.h"
#include "ssao/vao.h"

namespace exao::ssao {

/// SD-SVAO's phase 2. `map` is the stochastic depth map drawn with phase1.stencil.
[[nodiscard]] std::vector<float> sd_svao(const View& view, const VaoResult& phase1, const StochasticDepth& map,
                                         const Settings& settings, const VaoOptions& options);

/// Pixels phase 1 flagged (any bit set), in pixel order.
[[nodiscard]] std::vector<std::uint32_t> flagged_pixels(const VaoResult& phase1);

/// Every surface the segment from `from` to `to` crosses, appended to `out` as fractions of the
/// way in [0, 1], in any order. Called from many threads at once.
using SegmentHits = std::function<void(const glm::dvec3& from, const glm::dvec3& to, std::vector<double>& out)>;

/// SegmentHits from a nearest-hit query, closest(origin, unit direction) -> optional distance
/// (any face, t >= 0): the walk restarts a little past each hit, 1e-6 of the segment's length
/// (a crossing closer than that to the previous one is the same surface, or a shared edge), and
/// stops past the segment's end or after 256 crossings.
template <class Closest>
[[nodiscard]] SegmentHits segment_hits_by_closest(Closest closest) {
  return [closest](const glm::dvec3& from, const glm::dvec3& to, std::vector<double>& out) {
    const glm::dvec3 d = to - from;
    const double length = glm::length(d);
    if (!(length > 0.0)) return;
    const glm::dvec3 dir = d / length;
    const double skip = 1e-6 * length;
    double t = 0.0;
    for (int k = 0; k < 256; ++k) {
      const auto hit = closest(from + t * dir, dir);
      if (!hit) return;
      t += static_cast<double>(*hit);
      if (t > length) return;
      out.push_back(t / length);
      t += skip;
    }
  };
}

/// RT-SVAO in the paper's form: phase 1's AO with every flagged sample's column ray-cast through
/// `hits` (Sec. 3.8). Not clamped, like phase 1's.
[[nodiscard]] std::vector<float> rt_svao_columns(const View& view, const VaoResult& phase1, const Settings& settings,
                                                 const VaoOptions& options, const SegmentHits& hits);

/// RT-SVAO (exao's first form): phase 1's AO, with exact[k] at flagged_pixels(phase1)[k].
[[nodiscard]] std::vector<float> rt_svao(const VaoResult& phase1, std::span<const float> exact);

}  // namespace exao::ssao
