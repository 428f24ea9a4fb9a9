#pragma once
// exao::lut::Lanes: a few float operations over W lanes at once, in four twins (AVX-512: 16,
// AVX2: 8, SSE2: 4, scalar: 1), so that each sample kernel is written once as a template and
// compiled for the instruction set core/mask.h chose, and for the scalar twin the tests compare
// it to.
//
// Exactness: every twin evaluates the same expression tree with separate IEEE multiplies and
// adds (no FMA; exao_options builds with -ffp-contract=off), and the comparisons are ordered
// (false for NaN), so every twin gives the same bits for the same inputs. Lanes beyond N hold
// NaN, which fails every comparison, so their bits stay zero.

#include <cstdint>

#include "core/mask.h"

namespace exao::lut {

/// One lane: the scalar twin, the definition the vector lanes reproduce.
struct ScalarLanes {
  static constexpr int kWidth = 1;
  using F = float;
  using M = bool;
  static F load(const float* p) { return *p; }
  static F set(float x) { return x; }
  static F add(F a, F b) { return a + b; }
  static F sub(F a, F b) { return a - b; }
  static F mul(F a, F b) { return a * b; }
  // min/max as the x86 instructions define them: the second operand when either is NaN.
  static F min(F a, F b) { return a < b ? a : b; }
  static F max(F a, F b) { return a > b ? a : b; }
  static M ge(F a, F b) { return a >= b; }
  static M gt(F a, F b) { return a > b; }
  static M le(F a, F b) { return a <= b; }
  static M both(M a, M b) { return a && b; }
  static M either(M a, M b) { return a || b; }
  static std::uint64_t bits(M m) { return m ? 1u : 0u; }
};

#if defined(EXAO_SIMD_AVX512)
struct Avx512Lanes {
  static constexpr int kWidth = 16;
  using F = __m512;
  using M = __mmask16;
  static F load(const float* p) { return _mm512_load_ps(p); }
  static F set(float x) { return _mm512_set1_ps(x); }
  static F add(F a, F b) { return _mm512_add_ps(a, b); }
  static F sub(F a, F b) { return _mm512_sub_ps(a, b); }
  static F mul(F a, F b) { return _mm512_mul_ps(a, b); }
  // The masked forms: GCC 12's plain _mm512_min_ps warns from inside its own header.
  static F min(F a, F b) { return _mm512_mask_min_ps(a, 0xFFFF, a, b); }
  static F max(F a, F b) { return _mm512_mask_max_ps(a, 0xFFFF, a, b); }
  static M ge(F a, F b) { return _mm512_cmp_ps_mask(a, b, _CMP_GE_OQ); }
  static M gt(F a, F b) { return _mm512_cmp_ps_mask(a, b, _CMP_GT_OQ); }
  static M le(F a, F b) { return _mm512_cmp_ps_mask(a, b, _CMP_LE_OQ); }
  static M both(M a, M b) { return static_cast<M>(a & b); }
  static M either(M a, M b) { return static_cast<M>(a | b); }
  static std::uint64_t bits(M m) { return m; }
};
using NativeLanes = Avx512Lanes;
#elif defined(EXAO_SIMD_AVX2)
struct Avx2Lanes {
  static constexpr int kWidth = 8;
  using F = __m256;
  using M = __m256;  // all-ones or all-zeros per lane
  static F load(const float* p) { return _mm256_load_ps(p); }
  static F set(float x) { return _mm256_set1_ps(x); }
  static F add(F a, F b) { return _mm256_add_ps(a, b); }
  static F sub(F a, F b) { return _mm256_sub_ps(a, b); }
  static F mul(F a, F b) { return _mm256_mul_ps(a, b); }
  static F min(F a, F b) { return _mm256_min_ps(a, b); }
  static F max(F a, F b) { return _mm256_max_ps(a, b); }
  static M ge(F a, F b) { return _mm256_cmp_ps(a, b, _CMP_GE_OQ); }
  static M gt(F a, F b) { return _mm256_cmp_ps(a, b, _CMP_GT_OQ); }
  static M le(F a, F b) { return _mm256_cmp_ps(a, b, _CMP_LE_OQ); }
  static M both(M a, M b) { return _mm256_and_ps(a, b); }
  static M either(M a, M b) { return _mm256_or_ps(a, b); }
  static std::uint64_t bits(M m) { return static_cast<std::uint32_t>(_mm256_movemask_ps(m)); }
};
using NativeLanes = Avx2Lanes;
#elif defined(EXAO_SIMD_SSE2)
struct Sse2Lanes {
  static constexpr int kWidth = 4;
  using F = __m128;
  using M = __m128;  // all-ones or all-zeros per lane
  static F load(const float* p) { return _mm_load_ps(p); }
  static F set(float x) { return _mm_set1_ps(x); }
  static F add(F a, F b) { return _mm_add_ps(a, b); }
  static F sub(F a, F b) { return _mm_sub_ps(a, b); }
  static F mul(F a, F b) { return _mm_mul_ps(a, b); }
  static F min(F a, F b) { return _mm_min_ps(a, b); }
  static F max(F a, F b) { return _mm_max_ps(a, b); }
  static M ge(F a, F b) { return _mm_cmpge_ps(a, b); }
  static M gt(F a, F b) { return _mm_cmpgt_ps(a, b); }
  static M le(F a, F b) { return _mm_cmple_ps(a, b); }
  static M both(M a, M b) { return _mm_and_ps(a, b); }
  static M either(M a, M b) { return _mm_or_ps(a, b); }
  static std::uint64_t bits(M m) { return static_cast<std::uint32_t>(_mm_movemask_ps(m)); }
};
using NativeLanes = Sse2Lanes;
#else
using NativeLanes = ScalarLanes;
#endif

/// Builds a mask from a lane predicate: lanes(first) returns L::M for samples
/// [first, first + L::kWidth). The arrays the predicate reads are padded to Bits.
template <class L, int Bits, class Predicate>
[[nodiscard]] inline Mask<Bits> gather_bits(Predicate&& lanes) {
  Mask<Bits> mask;
  for (int w = 0; w < Mask<Bits>::kWords; ++w) {
    std::uint64_t word = 0;
    for (int k = 0; k < 64; k += L::kWidth) word |= L::bits(lanes(64 * w + k)) << k;
    mask.words[w] = word;
  }
  return mask;
}

}  // namespace exao::lut
