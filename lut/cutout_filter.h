#pragma once
// exao::lut::keep_cutout_hits / keep_cutout_sure: the masks' side of a cut-out (core/cutouts.h).
// A triangle mask says which rays meet an alpha-tested triangle; the alpha decides which of those
// it blocks, by the one decision Embree's filter calls too, ray by ray from the same floats. Only
// triangles with TriangleSet::cutout set come here, so an opaque scene never does.

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

#include "core/cutouts.h"
#include "core/receiver_frame.h"
#include "core/shadow_rays.h"
#include "lut/triangle_set.h"

namespace exao::lut {

/// Exact masks (brute, bvh): clears the bits of `mask` (a triangle mask of cut-out triangle
/// `scene_triangle`) whose ray the alpha lets through.
inline void keep_cutout_hits(const Cutouts& cutouts, std::uint32_t scene_triangle, const ShadowRays& rays,
                             const Frame& frame, std::span<std::uint64_t> mask) {
  filter_cutout_rays(cutouts, scene_triangle, rays, frame, mask);
}

/// Certain masks (auto): a sure bit is a ray that Embree surely finds hitting the triangle's
/// interior (lut/kernels-inl.h, "Certain masks"), so Embree's filter decides it by the same
/// decision: where it blocks, the bit stays sure; where the alpha lets it through, the ray surely
/// passes this triangle and leaves `maybe` too. Maybe bits that are not sure stay undecided, for
/// Embree and its filter.
template <std::size_t W>
inline void keep_cutout_sure(const Cutouts& cutouts, std::uint32_t scene_triangle, const ShadowRays& rays,
                             const Frame& frame, std::array<std::uint64_t, W>& sure,
                             std::array<std::uint64_t, W>& maybe) {
  std::array<std::uint64_t, W> passed = sure;
  filter_cutout_rays(cutouts, scene_triangle, rays, frame, passed);
  for (std::size_t w = 0; w < W; ++w) {
    maybe[w] &= ~(sure[w] & ~passed[w]);
    sure[w] = passed[w];
  }
}

}  // namespace exao::lut
