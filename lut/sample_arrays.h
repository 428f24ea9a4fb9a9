#pragma once
// exao::lut::SampleArrays: the shared sample pattern as structure-of-arrays floats, padded to the
// mask width and aligned to 64 bytes, so the exact kernels stream through them W lanes at a time.
// Also the exact plane kernels over those arrays (DESIGN.md section 4, "the exact test").

#include <cstddef>
#include <limits>
#include <new>
#include <vector>

#include "core/mask.h"
#include "core/sample_pattern.h"
#include "lut/lanes.h"
#include "lut/plane.h"

namespace exao::lut {

/// std::allocator with 64-byte alignment: one cache line, one AVX-512 load.
template <class T>
struct CacheLineAllocator {
  using value_type = T;
  static constexpr std::align_val_t kAlign{64};
  CacheLineAllocator() = default;
  template <class U>
  CacheLineAllocator(const CacheLineAllocator<U>&) {}  // NOLINT: rebinding must be implicit
  [[nodiscard]] T* allocate(std::size_t n) { return static_cast<T*>(::operator new(n * sizeof(T), kAlign)); }
  void deallocate(T* p, std::size_t) { ::operator delete(p, kAlign); }
  friend bool operator==(const CacheLineAllocator&, const CacheLineAllocator&) { return true; }
};

using AlignedFloats = std::vector<float, CacheLineAllocator<float>>;

class SampleArrays {
 public:
  SampleArrays() = default;
  /// Copies the pattern's points, directions and lengths (normalised units, r = 1) into arrays
  /// of mask_bits_for(N) floats each; entries N.. are NaN so that every comparison on them fails.
  explicit SampleArrays(const SamplePattern& pattern)
      : count_(pattern.count), bits_(mask_bits_for(pattern.count)) {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    for (AlignedFloats* a : {&px_, &py_, &pz_, &wx_, &wy_, &wz_, &length_}) {
      a->assign(static_cast<std::size_t>(bits_), nan);
    }
    for (int i = 0; i < count_; ++i) {
      px_[i] = pattern.points[i].x;
      py_[i] = pattern.points[i].y;
      pz_[i] = pattern.points[i].z;
      wx_[i] = pattern.directions[i].x;
      wy_[i] = pattern.directions[i].y;
      wz_[i] = pattern.directions[i].z;
      length_[i] = pattern.lengths[i];
    }
  }

  [[nodiscard]] int count() const { return count_; }  // N
  [[nodiscard]] int bits() const { return bits_; }    // padded length, the mask width
  // Sample points s_i = l_i w_i.
  [[nodiscard]] const float* px() const { return px_.data(); }
  [[nodiscard]] const float* py() const { return py_.data(); }
  [[nodiscard]] const float* pz() const { return pz_.data(); }
  // Unit directions w_i.
  [[nodiscard]] const float* wx() const { return wx_.data(); }
  [[nodiscard]] const float* wy() const { return wy_.data(); }
  [[nodiscard]] const float* wz() const { return wz_.data(); }
  // Lengths l_i in (0, 1].
  [[nodiscard]] const float* length() const { return length_.data(); }

 private:
  int count_ = 0;
  int bits_ = 0;
  AlignedFloats px_, py_, pz_, wx_, wy_, wz_, length_;
};

/// Bit i set iff point i (x[i], y[i], z[i]) is on the positive side of `plane`: the mask a
/// plane-table cell stores, and the exact test of one plane. Arrays of Bits floats, aligned.
template <class L, int Bits>
[[nodiscard]] Mask<Bits> plane_mask(const float* x, const float* y, const float* z, const Plane& plane) {
  const auto mx = L::set(plane.m.x), my = L::set(plane.m.y), mz = L::set(plane.m.z), d = L::set(plane.d);
  return gather_bits<L, Bits>([&](int i) {
    const auto dot = L::add(L::add(L::mul(mx, L::load(x + i)), L::mul(my, L::load(y + i))), L::mul(mz, L::load(z + i)));
    return L::ge(dot, d);
  });
}

/// Bit i set iff sample point i is on the positive side of all three edge planes (d = 0) and of
/// the triangle's plane: the exact triangle mask before the region clip (DESIGN.md section 4).
/// One pass over the points instead of four masks AND-ed.
template <class L, int Bits>
[[nodiscard]] Mask<Bits> triangle_planes_mask(const SampleArrays& samples, const Plane (&edge)[3], const Plane& face) {
  const auto e0x = L::set(edge[0].m.x), e0y = L::set(edge[0].m.y), e0z = L::set(edge[0].m.z);
  const auto e1x = L::set(edge[1].m.x), e1y = L::set(edge[1].m.y), e1z = L::set(edge[1].m.z);
  const auto e2x = L::set(edge[2].m.x), e2y = L::set(edge[2].m.y), e2z = L::set(edge[2].m.z);
  const auto fx = L::set(face.m.x), fy = L::set(face.m.y), fz = L::set(face.m.z), fd = L::set(face.d);
  const auto zero = L::set(0.0f);
  const float* px = samples.px();
  const float* py = samples.py();
  const float* pz = samples.pz();
  return gather_bits<L, Bits>([&](int i) {
    const auto x = L::load(px + i), y = L::load(py + i), z = L::load(pz + i);
    const auto dot = [&](auto mx, auto my, auto mz) {
      return L::add(L::add(L::mul(mx, x), L::mul(my, y)), L::mul(mz, z));
    };
    auto m = L::ge(dot(fx, fy, fz), fd);
    m = L::both(m, L::ge(dot(e0x, e0y, e0z), zero));
    m = L::both(m, L::ge(dot(e1x, e1y, e1z), zero));
    return L::both(m, L::ge(dot(e2x, e2y, e2z), zero));
  });
}

}  // namespace exao::lut
