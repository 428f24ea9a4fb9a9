#pragma once
// exao::Agreement: how two backends' masks of the same receivers agree (DESIGN.md section 8,
// test 3), ray by ray and receiver by receiver, with the rays that differ sorted into grazing
// (core/grazing.h: rounding may decide them) and not. What `exao bench`, `exao bake --compare`
// and the equality tests report.

#include <cstddef>
#include <span>

#include "core/ao_error.h"
#include "core/grazing.h"
#include "core/mask_set.h"
#include "core/receiver_frame.h"
#include "core/shadow_rays.h"

namespace exao {

struct Agreement {
  std::size_t receivers = 0;
  std::size_t rays = 0;
  std::size_t rays_differ = 0;          // rays whose blocked bit differs
  std::size_t identical_ao = 0;         // receivers with the same number of blocked rays
  std::size_t receivers_differ = 0;     // receivers with at least one differing ray
  // Filled only when a GrazingTest classifies the differing rays:
  bool classified = false;
  std::size_t rays_differ_grazing = 0;      // differing rays that graze a triangle
  std::size_t receivers_grazing = 0;        // receivers that differ only in grazing rays
  std::size_t ao_differ_not_grazing = 0;    // receivers whose AO differs by a ray that does not graze
  double largest_closeness = 0.0;           // the largest GrazingTest::closeness among grazing differing rays
  AoError ao;                               // AO against AO_reference

  [[nodiscard]] double ray_share() const { return rays ? 1.0 - double(rays_differ) / double(rays) : 1.0; }
  [[nodiscard]] double identical_share() const { return receivers ? double(identical_ao) / double(receivers) : 1.0; }
  /// Receivers whose AO is identical or differs only by grazing rays (needs classified).
  [[nodiscard]] double identical_or_grazing_share() const {
    return receivers ? 1.0 - double(ao_differ_not_grazing) / double(receivers) : 1.0;
  }
  [[nodiscard]] std::size_t rays_differ_not_grazing() const { return rays_differ - rays_differ_grazing; }
  Agreement& operator+=(const Agreement& other);
};

/// Compares `masks` with `reference` (the same receivers, in order, cast with `rays`). With
/// `grazing`, every differing ray is classified (O(scene triangles) per receiver that differs,
/// in parallel): cheap when the masks are exact, slow for table masks that differ on many rays.
[[nodiscard]] Agreement compare_masks(const MaskSet& reference, const MaskSet& masks, std::span<const Receiver> receivers,
                                      const ShadowRays& rays, const GrazingTest* grazing = nullptr);

}  // namespace exao
