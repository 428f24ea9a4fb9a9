#pragma once
// exao::lut::SampleArrays: the shared sample pattern as structure-of-arrays floats, padded to the
// mask width and aligned to 64 bytes, so the kernels stream through them W lanes at a time; and
// the pattern's clusters: each run of kSampleCluster consecutive samples (bits [16k, 16k + 16) of
// a mask) with the cone that bounds its directions, so that a kernel can skip a whole cluster
// that a triangle or a sphere provably cannot reach (lut/kernels-inl.h). The clusters change
// what is computed, never the answer.

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <numbers>
#include <new>
#include <vector>

#include "core/mask.h"
#include "core/sample_pattern.h"

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

/// Clusters of a mask of Bits bits: Bits / kSampleCluster, at most 64 (one bit each in a word).
[[nodiscard]] constexpr int clusters_for_bits(int bits) { return bits / kSampleCluster; }

/// The set of every cluster of a Bits-bit mask, one bit per cluster.
template <int Bits>
inline constexpr std::uint64_t kAllClusters =
    clusters_for_bits(Bits) == 64 ? ~std::uint64_t{0} : (std::uint64_t{1} << clusters_for_bits(Bits)) - 1;

/// The clusters in which `mask` has a bit set.
template <int Bits>
[[nodiscard]] inline std::uint64_t occupied_clusters(const Mask<Bits>& mask) {
  std::uint64_t clusters = 0;
  for (int w = 0; w < Mask<Bits>::kWords; ++w) {
    for (int j = 0; j < 4; ++j) {
      if ((mask.words[w] >> (16 * j)) & 0xFFFFu) clusters |= std::uint64_t{1} << (4 * w + j);
    }
  }
  return clusters;
}

/// The clusters in which `mask` still has a bit clear among the first n samples: where more
/// occlusion can be found. (Clusters past n hold no samples and count as full.)
template <int Bits>
[[nodiscard]] inline std::uint64_t open_clusters(const Mask<Bits>& mask, int n) {
  std::uint64_t clusters = 0;
  const int count = n / kSampleCluster;
  for (int k = 0; k < count; ++k) {
    if (((mask.words[k >> 2] >> (16 * (k & 3))) & 0xFFFFu) != 0xFFFFu) clusters |= std::uint64_t{1} << k;
  }
  return clusters;
}

/// The mask with every bit of the clusters in `clusters` set (among the first Bits bits).
template <int Bits>
[[nodiscard]] inline Mask<Bits> cluster_bits(std::uint64_t clusters) {
  Mask<Bits> m;
  for (int k = 0; k < clusters_for_bits(Bits); ++k) {
    if ((clusters >> k) & 1u) m.words[k >> 2] |= std::uint64_t{0xFFFF} << (16 * (k & 3));
  }
  return m;
}

class SampleArrays {
 public:
  SampleArrays() = default;
  /// Copies the pattern's points, directions and lengths (normalised units, r = 1) into arrays
  /// of mask_bits_for(N) floats each; entries N.. are NaN so that every comparison on them fails.
  /// Computes each cluster's cone: its axis (the normalised mean direction) and half-angle, with
  /// the cosine rounded down and the sine rounded up (conservative). Padding clusters get a cone
  /// no test can reach (cos = 2, sin = -2).
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
    // Cluster arrays padded to 16 floats at least: one AVX-512 load covers all of N <= 256.
    const int clusters = clusters_for_bits(bits_);
    const std::size_t padded = static_cast<std::size_t>(std::max(16, clusters));
    for (AlignedFloats* a : {&cx_, &cy_, &cz_}) a->assign(padded, 0.0f);
    ccos_.assign(padded, 2.0f);
    csin_.assign(padded, -2.0f);
    for (int k = 0; k < count_ / kSampleCluster; ++k) {
      glm::dvec3 sum(0.0);
      for (int i = kSampleCluster * k; i < kSampleCluster * (k + 1); ++i) sum += glm::dvec3(pattern.directions[i]);
      const glm::vec3 axis(glm::normalize(sum));
      double widest = 0.0;
      for (int i = kSampleCluster * k; i < kSampleCluster * (k + 1); ++i) {
        const double c = glm::dot(glm::dvec3(axis), glm::dvec3(pattern.directions[i]));
        widest = std::max(widest, std::acos(std::clamp(c, -1.0, 1.0)));
      }
      widest += 1e-6;  // the float axis and directions, taken as exact, are within this
      cx_[k] = axis.x;
      cy_[k] = axis.y;
      cz_[k] = axis.z;
      ccos_[k] = std::nextafter(static_cast<float>(std::cos(widest)), -1.0f);
      csin_[k] = std::nextafter(static_cast<float>(std::sin(widest)), 2.0f);
      // The kernels' cone tests (lut/kernels-inl.h: edge planes by -sin, spheres by
      // cos(theta_k + theta_s)) bound a cone of half-angle at most pi/2; past it sin falls again
      // and they would cull rays they reach. A cluster that wide (a caller's own directions in
      // an incoherent order, make_given_pattern) gets the bounds of the hemisphere instead,
      // which every test passes: cos -1 and sin 1, rounded outwards.
      if (widest > 0.5 * std::numbers::pi) {
        ccos_[k] = -1.0f;
        csin_[k] = std::nextafter(1.0f, 2.0f);
      }
    }
    build_grid();
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
  // Cluster cones: unit axes, cosine (rounded down) and sine (rounded up) of the half-angles.
  [[nodiscard]] const float* cluster_x() const { return cx_.data(); }
  [[nodiscard]] const float* cluster_y() const { return cy_.data(); }
  [[nodiscard]] const float* cluster_z() const { return cz_.data(); }
  [[nodiscard]] const float* cluster_cos() const { return ccos_.data(); }
  [[nodiscard]] const float* cluster_sin() const { return csin_.data(); }

  // The direction grid: G x G cells over [-1, 1]^2 of (w.x, w.y), about one sample per cell;
  // cell (i, j) holds samples grid_samples()[grid_start()[j G + i] .. grid_start()[j G + i + 1]).
  // A kernel whose cone is small finds its few candidate samples here instead of testing every
  // cluster (lut/kernels-inl.h, near_samples).
  [[nodiscard]] int grid_size() const { return grid_size_; }
  [[nodiscard]] const std::uint16_t* grid_start() const { return grid_start_.data(); }
  [[nodiscard]] const std::uint16_t* grid_samples() const { return grid_samples_.data(); }
  /// The grid cell of a coordinate in [-1, 1] (clamped): the one formula every user calls.
  [[nodiscard]] int grid_cell(float x) const {
    const float cell = std::floor((x + 1.0f) * (0.5f * static_cast<float>(grid_size_)));
    return static_cast<int>(std::clamp(cell, 0.0f, static_cast<float>(grid_size_ - 1)));
  }

 private:
  int count_ = 0;
  int bits_ = 0;
  AlignedFloats px_, py_, pz_, wx_, wy_, wz_, length_;
  AlignedFloats cx_, cy_, cz_, ccos_, csin_;
  int grid_size_ = 1;
  std::vector<std::uint16_t> grid_start_, grid_samples_;

  void build_grid() {
    // The disc covers pi/4 of the square: G^2 ~ 4N/pi cells give about one sample per cell.
    grid_size_ = std::max(4, static_cast<int>(std::ceil(std::sqrt(4.0 * count_ / 3.14159265))));
    const int cells = grid_size_ * grid_size_;
    std::vector<int> cell_of(static_cast<std::size_t>(count_));
    grid_start_.assign(static_cast<std::size_t>(cells) + 1, 0);
    for (int i = 0; i < count_; ++i) {
      cell_of[i] = grid_cell(wy_[i]) * grid_size_ + grid_cell(wx_[i]);
      ++grid_start_[static_cast<std::size_t>(cell_of[i]) + 1];
    }
    for (int c = 0; c < cells; ++c) grid_start_[c + 1] = static_cast<std::uint16_t>(grid_start_[c + 1] + grid_start_[c]);
    grid_samples_.assign(static_cast<std::size_t>(count_), 0);
    std::vector<int> next(grid_start_.begin(), grid_start_.end() - 1);
    for (int i = 0; i < count_; ++i) grid_samples_[next[cell_of[i]]++] = static_cast<std::uint16_t>(i);
  }
};

}  // namespace exao::lut
