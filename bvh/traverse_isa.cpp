// The BVH traversal for one instruction set: compiled once per level of core/isa.h, with
// EXAO_KERNEL_ISA_<LEVEL> defined (CMake's exao_kernel_objects).
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

#include <immintrin.h>

#include "bvh/traverse.h"
#include "core/grazing.h"
#include "core/surface_rule.h"
#include "lut/cutout_filter.h"
#include "lut/mask_kernels.h"
#include "lut/sphere_test.h"

#include "core/kernel_target.h"

namespace exao::bvh::EXAO_KERNEL_NS {

using lut::KernelContext;
using lut::KernelCounters;
using lut::PackedTriangle;
using lut::Plane;
using lut::SampleArrays;
using lut::SphereTest;
using lut::TriangleSet;
using lut::cluster_bits;
using lut::clusters_for_bits;
using lut::kAllClusters;
using lut::kTriangleMargin;
using lut::make_sphere_test;
using lut::occupied_clusters;
using lut::origin_triangle_distance2;

#include "core/lanes-inl.h"
#include "lut/kernels-inl.h"
#include "bvh/leaf_setup-inl.h"
#include "bvh/node_setup-inl.h"
#include "bvh/traverse-inl.h"

namespace {

template <int Bits>
constexpr TraverseFunctions<Bits> functions() {
  return {&traverse_receiver<Bits, false, false>, &traverse_receiver<Bits, true, false>,
          &traverse_receiver<Bits, false, true>, &traverse_receiver<Bits, true, true>, &leaf_masks<Bits>};
}

}  // namespace

const TraverseTable& traverse_table() {
  static const TraverseTable table{functions<64>(), functions<128>(), functions<256>(), functions<512>(),
                                   functions<1024>()};
  return table;
}

}  // namespace exao::bvh::EXAO_KERNEL_NS

#include "core/kernel_target_end.h"
