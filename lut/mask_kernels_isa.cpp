// The mask kernels for one instruction set: compiled once per level of core/isa.h, with
// EXAO_KERNEL_ISA_<LEVEL> defined (CMake's exao_kernel_objects).
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

#include <immintrin.h>

#include "core/surface_rule.h"
#include "lut/mask_kernels.h"
#include "lut/sphere_test.h"

#include "core/kernel_target.h"

namespace exao::lut::EXAO_KERNEL_NS {

#include "core/lanes-inl.h"
#include "lut/kernels-inl.h"

namespace {

template <int Bits>
Mask<Bits> triangle_entry(const KernelContext& ctx, const TriangleSet& triangles, std::uint32_t t, const Frame& frame,
                          std::uint64_t allowed, KernelCounters* counters) {
  return triangle_mask<Bits>(ctx, triangles, t, frame, allowed, counters);
}
template <int Bits>
Mask<Bits> region_entry(const KernelContext& ctx, const glm::vec3& centre, float radius, float margin,
                        std::uint64_t allowed, KernelCounters* counters) {
  return region_mask<Bits>(ctx, centre, radius, margin, allowed, counters);
}
template <int Bits>
Mask<Bits> plane_entry(const float* x, const float* y, const float* z, const Plane& plane) {
  return plane_mask<Bits>(x, y, z, plane);
}
template <int Bits>
constexpr KernelFunctions<Bits> functions() {
  return {&triangle_entry<Bits>, &region_entry<Bits>, &plane_entry<Bits>};
}

}  // namespace

const MaskKernels& kernels() {
  static const MaskKernels table{EXAO_KERNEL_ISA, functions<64>(), functions<128>(), functions<256>(),
                                 functions<512>(), functions<1024>()};
  return table;
}

}  // namespace exao::lut::EXAO_KERNEL_NS

#include "core/kernel_target_end.h"
