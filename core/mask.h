#pragma once
// Mask<Bits>: the N-bit occlusion mask of one receiver (DESIGN.md section 4). Bit i set means
// shadow ray i is blocked. Bits is the storage width, a power of two from 64 to 1024; the
// pattern's N (a multiple of 32) uses the first N bits and every bit >= N stays zero, which every
// operation here preserves (none of them sets a bit that neither operand had, except ones(n)).
//
// The instruction set the kernels run is chosen at run time, in core/isa.h (one copy of each
// kernel per level, core/kernel_target.h; the engine reports the one it runs). What is chosen
// here, at compile time, is only how the mask word operations below are written in this
// translation unit (a kernel copy compiled for a level sees that level's macros):
//   EXAO_SIMD_AVX512  AVX-512 F/BW/VL 512-bit registers (and VPOPCNTDQ when present);
//   EXAO_SIMD_AVX2    AVX2 256-bit registers;
//   EXAO_SIMD_SSE2    SSE2, which every x86-64 has;
//   none              64-bit words (also forced with -DEXAO_FORCE_SCALAR, the CMake option
//                     EXAO_FORCE_SCALAR of lut/).
// Every vectorised operation has a scalar twin in exao::scalar, and tests/mask_test.cpp checks
// that both agree bit for bit.

#include <array>
#include <bit>
#include <cassert>
#include <cstddef>
#include <cstdint>
#include <span>
#include <type_traits>

#if !defined(EXAO_FORCE_SCALAR)
#if defined(__AVX512F__) && defined(__AVX512BW__) && defined(__AVX512VL__)
#define EXAO_SIMD_AVX512 1
#elif defined(__AVX2__)
#define EXAO_SIMD_AVX2 1
#elif defined(__SSE2__)
#define EXAO_SIMD_SSE2 1
#endif
#endif

#if defined(EXAO_SIMD_AVX512) || defined(EXAO_SIMD_AVX2) || defined(EXAO_SIMD_SSE2)
#include <immintrin.h>
#endif

namespace exao {

/// The instruction set this translation unit's mask word operations were compiled for: "avx512",
/// "avx2", "sse2" or "scalar". Not the level the kernels run: that is core/isa.h's choice.
[[nodiscard]] constexpr const char* simd_name() {
#if defined(EXAO_SIMD_AVX512)
  return "avx512";
#elif defined(EXAO_SIMD_AVX2)
  return "avx2";
#elif defined(EXAO_SIMD_SSE2)
  return "sse2";
#else
  return "scalar";
#endif
}

/// True for the storage widths a Mask comes in.
[[nodiscard]] constexpr bool valid_mask_bits(int bits) {
  return bits == 64 || bits == 128 || bits == 256 || bits == 512 || bits == 1024;
}

/// The smallest storage width that holds `samples` bits (samples in [1, 1024]).
[[nodiscard]] constexpr int mask_bits_for(int samples) {
  return samples <= 64 ? 64 : samples <= 128 ? 128 : samples <= 256 ? 256 : samples <= 512 ? 512 : 1024;
}

/// Alignment of a Mask: its size up to 16 bytes. Not more: masks cross between code compiled for
/// different instruction sets (lut/mask_kernels.h), and GCC 12 does not always give a 64-byte
/// aligned return slot to a callee that assumes one; the vector paths below load unaligned.
template <int Bits>
inline constexpr std::size_t kMaskAlign = Bits / 8 < 16 ? Bits / 8 : 16;

template <int Bits>
struct alignas(kMaskAlign<Bits>) Mask {
  static_assert(valid_mask_bits(Bits), "Mask<Bits>: Bits must be 64, 128, 256, 512 or 1024");
  static constexpr int kBits = Bits;
  static constexpr int kWords = Bits / 64;

  std::array<std::uint64_t, kWords> words{};  // bit i is words[i / 64] >> (i % 64)

  /// The first n bits set, n in [0, Bits].
  [[nodiscard]] static constexpr Mask ones(int n) {
    assert(n >= 0 && n <= Bits);
    Mask m;
    for (int w = 0; w < kWords; ++w) {
      const int left = n - 64 * w;
      m.words[w] = left >= 64 ? ~std::uint64_t{0} : left <= 0 ? 0 : (std::uint64_t{1} << left) - 1;
    }
    return m;
  }

  [[nodiscard]] constexpr bool test(int i) const {
    assert(i >= 0 && i < Bits);
    return (words[i >> 6] >> (i & 63)) & 1u;
  }
  constexpr void set(int i) {
    assert(i >= 0 && i < Bits);
    words[i >> 6] |= std::uint64_t{1} << (i & 63);
  }

  [[nodiscard]] int popcount() const;
  [[nodiscard]] bool any() const;
  [[nodiscard]] bool none() const { return !any(); }

  Mask& operator|=(const Mask& o);
  Mask& operator&=(const Mask& o);
  [[nodiscard]] friend Mask operator|(Mask a, const Mask& b) { return a |= b; }
  [[nodiscard]] friend Mask operator&(Mask a, const Mask& b) { return a &= b; }
  [[nodiscard]] friend bool operator==(const Mask& a, const Mask& b) { return a.words == b.words; }
};

// --- The scalar twin: word by word, the definition the vector code must reproduce. ----------
namespace scalar {

template <int Bits>
[[nodiscard]] constexpr Mask<Bits> or_(const Mask<Bits>& a, const Mask<Bits>& b) {
  Mask<Bits> r;
  for (int w = 0; w < Mask<Bits>::kWords; ++w) r.words[w] = a.words[w] | b.words[w];
  return r;
}
template <int Bits>
[[nodiscard]] constexpr Mask<Bits> and_(const Mask<Bits>& a, const Mask<Bits>& b) {
  Mask<Bits> r;
  for (int w = 0; w < Mask<Bits>::kWords; ++w) r.words[w] = a.words[w] & b.words[w];
  return r;
}
template <int Bits>
[[nodiscard]] constexpr Mask<Bits> and_not(const Mask<Bits>& a, const Mask<Bits>& b) {
  Mask<Bits> r;
  for (int w = 0; w < Mask<Bits>::kWords; ++w) r.words[w] = a.words[w] & ~b.words[w];
  return r;
}
template <int Bits>
[[nodiscard]] constexpr int popcount(const Mask<Bits>& a) {
  int n = 0;
  for (const std::uint64_t w : a.words) n += std::popcount(w);
  return n;
}
template <int Bits>
[[nodiscard]] constexpr bool any(const Mask<Bits>& a) {
  std::uint64_t acc = 0;
  for (const std::uint64_t w : a.words) acc |= w;
  return acc != 0;
}
template <int Bits>
[[nodiscard]] constexpr int popcount_and_not(const Mask<Bits>& a, const Mask<Bits>& b) {
  int n = 0;
  for (int w = 0; w < Mask<Bits>::kWords; ++w) n += std::popcount(a.words[w] & ~b.words[w]);
  return n;
}

}  // namespace scalar

// --- The vector versions. -------------------------------------------------------------------
// Masks of 64 and 128 bits are one or two general-purpose words: the scalar code is already
// optimal there (and the compiler keeps them in registers), so the intrinsics start at 256.
namespace simd_detail {

// The bitwise operations use GCC/Clang vector operators (x & ~y) rather than the _mm512_and*
// intrinsics: same instructions, without GCC 12's false -Wmaybe-uninitialized from inside
// the intrinsic headers.
#if defined(EXAO_SIMD_AVX512)
inline int horizontal_sum(__m512i v) {
  alignas(64) std::uint64_t lanes[8];
  _mm512_store_si512(lanes, v);
  std::uint64_t sum = 0;
  for (const std::uint64_t x : lanes) sum += x;
  return static_cast<int>(sum);
}

// Bits >= 512: whole zmm registers.
template <int Bits, class Op>
inline void zip512(std::uint64_t* r, const std::uint64_t* a, const std::uint64_t* b, Op op) {
  for (int w = 0; w < Bits / 64; w += 8) {
    const __m512i x = _mm512_loadu_si512(a + w);
    const __m512i y = _mm512_loadu_si512(b + w);
    _mm512_storeu_si512(r + w, op(x, y));
  }
}
#endif
#if defined(EXAO_SIMD_AVX512) || defined(EXAO_SIMD_AVX2)
template <int Bits, class Op>
inline void zip256(std::uint64_t* r, const std::uint64_t* a, const std::uint64_t* b, Op op) {
  for (int w = 0; w < Bits / 64; w += 4) {
    const __m256i x = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(a + w));
    const __m256i y = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(b + w));
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(r + w), op(x, y));
  }
}
#endif

}  // namespace simd_detail

template <int Bits>
inline Mask<Bits>& Mask<Bits>::operator|=(const Mask& o) {
#if defined(EXAO_SIMD_AVX512)
  if constexpr (Bits >= 512) {
    simd_detail::zip512<Bits>(words.data(), words.data(), o.words.data(),
                              [](__m512i x, __m512i y) { return x | y; });
    return *this;
  }
#endif
#if defined(EXAO_SIMD_AVX512) || defined(EXAO_SIMD_AVX2)
  if constexpr (Bits >= 256) {
    simd_detail::zip256<Bits>(words.data(), words.data(), o.words.data(),
                              [](__m256i x, __m256i y) { return x | y; });
    return *this;
  }
#endif
  return *this = scalar::or_(*this, o);
}

template <int Bits>
inline Mask<Bits>& Mask<Bits>::operator&=(const Mask& o) {
#if defined(EXAO_SIMD_AVX512)
  if constexpr (Bits >= 512) {
    simd_detail::zip512<Bits>(words.data(), words.data(), o.words.data(),
                              [](__m512i x, __m512i y) { return x & y; });
    return *this;
  }
#endif
#if defined(EXAO_SIMD_AVX512) || defined(EXAO_SIMD_AVX2)
  if constexpr (Bits >= 256) {
    simd_detail::zip256<Bits>(words.data(), words.data(), o.words.data(),
                              [](__m256i x, __m256i y) { return x & y; });
    return *this;
  }
#endif
  return *this = scalar::and_(*this, o);
}

/// a & ~b: the bits of a that b does not have (e.g. node mask & ~cumulative).
template <int Bits>
[[nodiscard]] inline Mask<Bits> and_not(const Mask<Bits>& a, const Mask<Bits>& b) {
  Mask<Bits> r;
#if defined(EXAO_SIMD_AVX512)
  if constexpr (Bits >= 512) {
    simd_detail::zip512<Bits>(r.words.data(), a.words.data(), b.words.data(),
                              [](__m512i x, __m512i y) { return x & ~y; });
    return r;
  }
#endif
#if defined(EXAO_SIMD_AVX512) || defined(EXAO_SIMD_AVX2)
  if constexpr (Bits >= 256) {
    simd_detail::zip256<Bits>(r.words.data(), a.words.data(), b.words.data(),
                              [](__m256i x, __m256i y) { return x & ~y; });
    return r;
  }
#endif
  return scalar::and_not(a, b);
}

template <int Bits>
inline int Mask<Bits>::popcount() const {
#if defined(EXAO_SIMD_AVX512) && defined(__AVX512VPOPCNTDQ__)
  if constexpr (Bits >= 512) {
    __m512i sum = _mm512_setzero_si512();
    for (int w = 0; w < kWords; w += 8) {
      sum = _mm512_add_epi64(sum, _mm512_popcnt_epi64(_mm512_loadu_si512(words.data() + w)));
    }
    return simd_detail::horizontal_sum(sum);
  }
#endif
  // Below 512 bits (or without VPOPCNTDQ) one POPCNT per word is as fast as it gets.
  return scalar::popcount(*this);
}

template <int Bits>
inline bool Mask<Bits>::any() const {
#if defined(EXAO_SIMD_AVX512)
  if constexpr (Bits >= 512) {
    __m512i acc = _mm512_loadu_si512(words.data());
    for (int w = 8; w < kWords; w += 8) acc = _mm512_or_si512(acc, _mm512_loadu_si512(words.data() + w));
    return _mm512_test_epi64_mask(acc, acc) != 0;
  }
#endif
#if defined(EXAO_SIMD_AVX512) || defined(EXAO_SIMD_AVX2)
  if constexpr (Bits >= 256) {
    __m256i acc = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(words.data()));
    for (int w = 4; w < kWords; w += 4) {
      acc = _mm256_or_si256(acc, _mm256_loadu_si256(reinterpret_cast<const __m256i*>(words.data() + w)));
    }
    return !_mm256_testz_si256(acc, acc);
  }
#endif
  return scalar::any(*this);
}

/// popcount(a & ~b) without the temporary: the BVH's "rays this node could still block".
template <int Bits>
[[nodiscard]] inline int popcount_and_not(const Mask<Bits>& a, const Mask<Bits>& b) {
#if defined(EXAO_SIMD_AVX512) && defined(__AVX512VPOPCNTDQ__)
  if constexpr (Bits >= 512) {
    __m512i sum = _mm512_setzero_si512();
    for (int w = 0; w < Mask<Bits>::kWords; w += 8) {
      const __m512i x = _mm512_loadu_si512(a.words.data() + w) & ~_mm512_loadu_si512(b.words.data() + w);
      sum = _mm512_add_epi64(sum, _mm512_popcnt_epi64(x));
    }
    return simd_detail::horizontal_sum(sum);
  }
#endif
  return scalar::popcount_and_not(a, b);
}

/// Calls f(std::integral_constant<int, Bits>{}) with the smallest Bits >= samples, samples in
/// [1, 1024]: the one place a run-time N becomes a compile-time mask width.
template <class F>
decltype(auto) with_mask_bits(int samples, F&& f) {
  assert(samples >= 1 && samples <= 1024);
  switch (mask_bits_for(samples)) {
    case 64: return f(std::integral_constant<int, 64>{});
    case 128: return f(std::integral_constant<int, 128>{});
    case 256: return f(std::integral_constant<int, 256>{});
    case 512: return f(std::integral_constant<int, 512>{});
    default: return f(std::integral_constant<int, 1024>{});
  }
}

/// Writes the first row.size() words of `mask` into `row` (a MaskSet row: N/64 rounded up
/// words, at most Bits/64).
template <int Bits>
void store(const Mask<Bits>& mask, std::span<std::uint64_t> row) {
  assert(row.size() <= static_cast<std::size_t>(Mask<Bits>::kWords));
  for (std::size_t w = 0; w < row.size(); ++w) row[w] = mask.words[w];
}

/// Reads a MaskSet row (row.size() <= Bits/64 words) into a mask; the rest stays zero.
template <int Bits>
[[nodiscard]] Mask<Bits> load_mask(std::span<const std::uint64_t> row) {
  assert(row.size() <= static_cast<std::size_t>(Mask<Bits>::kWords));
  Mask<Bits> m;
  for (std::size_t w = 0; w < row.size(); ++w) m.words[w] = row[w];
  return m;
}

}  // namespace exao
