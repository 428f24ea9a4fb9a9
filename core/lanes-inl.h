// Lanes: a few float operations over W lanes at once, for the instruction set of the
// translation unit that includes this file, inside that level's namespace (lut::<isa> for the
// mask kernels, bvh::<isa> for the traversal: both sit above core, where this lives).
// core/kernel_target.h sets EXAO_KERNEL_LANES and the matching `#pragma GCC target`, so that
// each kernel is written once and compiled for every level of core/isa.h. No include guard: it
// is included once per instruction set, inside that set's namespace.
//
// Exactness: every level evaluates the same expression tree with separate IEEE multiplies and
// adds (no FMA; exao_options builds with -ffp-contract=off), and the comparisons are ordered
// (false for NaN), so every level gives the same bits for the same inputs. Lanes beyond N hold
// NaN, which fails every comparison, so their bits stay zero.

// Lanes8 is the same over 8 floats (the scalar twin: 1), for the set-up of a BVH leaf of up to
// 8 triangles, lane = triangle (bvh/leaf_setup-inl.h): AVX at the AVX2 and AVX-512 levels, SSE
// (4 lanes, two steps) below, one lane for the scalar twin. Lanes4 is SSE (or one lane), for the
// four children of a BVH node (bvh/node_setup-inl.h).
#if EXAO_KERNEL_LANES == 1
// One lane: the scalar twin, the definition the vector lanes reproduce.
struct Lanes {
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
  static M le(F a, F b) { return a <= b; }
  static M both(M a, M b) { return a && b; }
  static std::uint64_t bits(M m) { return m ? 1u : 0u; }
  static void store(float* p, F a) { *p = a; }
  static F div(F a, F b) { return a / b; }
  static F sqrt(F a) { return std::sqrt(a); }
  static F abs(F a) { return std::abs(a); }
  static M gt(F a, F b) { return a > b; }
  static M lt(F a, F b) { return a < b; }
  static M either(M a, M b) { return a || b; }
  static M not_(M a) { return !a; }
  static M from_bits(std::uint32_t b) { return (b & 1u) != 0; }
  static F select(M m, F if_true, F if_false) { return m ? if_true : if_false; }
  static F neg(F a) { return -a; }
  static F loadu(const float* p) { return *p; }
};
using Lanes8 = Lanes;
using Lanes4 = Lanes;
#elif EXAO_KERNEL_LANES == 16
struct Lanes {
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
  static M le(F a, F b) { return _mm512_cmp_ps_mask(a, b, _CMP_LE_OQ); }
  static M both(M a, M b) { return static_cast<M>(a & b); }
  static std::uint64_t bits(M m) { return m; }
  static void store(float* p, F a) { _mm512_store_ps(p, a); }
  static F div(F a, F b) { return _mm512_div_ps(a, b); }
  static M lt(F a, F b) { return _mm512_cmp_ps_mask(a, b, _CMP_LT_OQ); }
  static F abs(F a) { return _mm512_abs_ps(a); }
  static F select(M m, F if_true, F if_false) { return _mm512_mask_blend_ps(m, if_false, if_true); }
};

#elif EXAO_KERNEL_LANES == 8
struct Lanes {
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
  static M le(F a, F b) { return _mm256_cmp_ps(a, b, _CMP_LE_OQ); }
  static M both(M a, M b) { return _mm256_and_ps(a, b); }
  static std::uint64_t bits(M m) { return static_cast<std::uint32_t>(_mm256_movemask_ps(m)); }
  static void store(float* p, F a) { _mm256_store_ps(p, a); }
  static F div(F a, F b) { return _mm256_div_ps(a, b); }
  static M lt(F a, F b) { return _mm256_cmp_ps(a, b, _CMP_LT_OQ); }
  static F abs(F a) { return _mm256_andnot_ps(_mm256_set1_ps(-0.0f), a); }
  static F select(M m, F if_true, F if_false) { return _mm256_blendv_ps(if_false, if_true, m); }
};
#elif EXAO_KERNEL_LANES == 4
struct Lanes {
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
  static M le(F a, F b) { return _mm_cmple_ps(a, b); }
  static M both(M a, M b) { return _mm_and_ps(a, b); }
  static std::uint64_t bits(M m) { return static_cast<std::uint32_t>(_mm_movemask_ps(m)); }
  static void store(float* p, F a) { _mm_store_ps(p, a); }
  static F div(F a, F b) { return _mm_div_ps(a, b); }
  static M lt(F a, F b) { return _mm_cmplt_ps(a, b); }
  static F abs(F a) { return _mm_andnot_ps(_mm_set1_ps(-0.0f), a); }
  static F select(M m, F if_true, F if_false) { return _mm_or_ps(_mm_and_ps(m, if_true), _mm_andnot_ps(m, if_false)); }
};
#else
#error "EXAO_KERNEL_LANES must be 1, 4, 8 or 16 (include core/kernel_target.h first)"
#endif

#if EXAO_KERNEL_LANES >= 4
// Four floats in SSE registers: Lanes8 below AVX, and Lanes4 (a node's children) at every vector level.
struct LanesSse {
  static constexpr int kWidth = 4;
  using F = __m128;
  using M = __m128;
  static F load(const float* p) { return _mm_load_ps(p); }
  static F loadu(const float* p) { return _mm_loadu_ps(p); }
  // Two floats into the low lanes, NaN above: a BVH leaf's row of 2 (bvh::leaf_width).
  static F load2(const float* p) {
    std::uint64_t two;
    std::memcpy(&two, p, sizeof two);
    const __m128 low = _mm_castsi128_ps(_mm_cvtsi64_si128(static_cast<long long>(two)));
    return _mm_movelh_ps(low, _mm_set1_ps(std::numeric_limits<float>::quiet_NaN()));
  }
  static F max(F a, F b) { return _mm_max_ps(a, b); }
  static F set(float x) { return _mm_set1_ps(x); }
  static F add(F a, F b) { return _mm_add_ps(a, b); }
  static F sub(F a, F b) { return _mm_sub_ps(a, b); }
  static F mul(F a, F b) { return _mm_mul_ps(a, b); }
  static F div(F a, F b) { return _mm_div_ps(a, b); }
  static F sqrt(F a) { return _mm_sqrt_ps(a); }
  static F abs(F a) { return _mm_andnot_ps(_mm_set1_ps(-0.0f), a); }
  static M ge(F a, F b) { return _mm_cmpge_ps(a, b); }
  static M le(F a, F b) { return _mm_cmple_ps(a, b); }
  static M gt(F a, F b) { return _mm_cmpgt_ps(a, b); }
  static M lt(F a, F b) { return _mm_cmplt_ps(a, b); }
  static M both(M a, M b) { return _mm_and_ps(a, b); }
  static M either(M a, M b) { return _mm_or_ps(a, b); }
  static M not_(M a) { return _mm_xor_ps(a, _mm_castsi128_ps(_mm_set1_epi32(-1))); }
  static M from_bits(std::uint32_t b) {
    const __m128i bit = _mm_setr_epi32(1, 2, 4, 8);
    return _mm_castsi128_ps(_mm_cmpeq_epi32(_mm_and_si128(_mm_set1_epi32(static_cast<int>(b)), bit), bit));
  }
  // SSE2 has no blendv.
  static F select(M m, F if_true, F if_false) { return _mm_or_ps(_mm_and_ps(m, if_true), _mm_andnot_ps(m, if_false)); }
  static F neg(F a) { return _mm_xor_ps(a, _mm_set1_ps(-0.0f)); }
  static void store(float* p, F a) { _mm_store_ps(p, a); }
  static std::uint64_t bits(M m) { return static_cast<std::uint32_t>(_mm_movemask_ps(m)); }
};
using Lanes4 = LanesSse;
#endif

#if EXAO_KERNEL_LANES >= 8
struct Lanes8 {
  static constexpr int kWidth = 8;
  using F = __m256;
  using M = __m256;  // all-ones or all-zeros per lane
  static F load(const float* p) { return _mm256_load_ps(p); }
  // The first n floats at p into the low lanes, NaN above (a BVH leaf's row of n, bvh::leaf_width),
  // without a branch on n: leaves of every width come in any order. Masked lanes are not read.
  static F load_first(const float* p, int n) {
    const __m256i keep = _mm256_cmpgt_epi32(_mm256_set1_epi32(n), _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7));
    return _mm256_blendv_ps(_mm256_set1_ps(std::numeric_limits<float>::quiet_NaN()), _mm256_maskload_ps(p, keep),
                            _mm256_castsi256_ps(keep));
  }
  static F set(float x) { return _mm256_set1_ps(x); }
  static F add(F a, F b) { return _mm256_add_ps(a, b); }
  static F sub(F a, F b) { return _mm256_sub_ps(a, b); }
  static F mul(F a, F b) { return _mm256_mul_ps(a, b); }
  static F div(F a, F b) { return _mm256_div_ps(a, b); }
  static F sqrt(F a) { return _mm256_sqrt_ps(a); }
  static F abs(F a) { return _mm256_andnot_ps(_mm256_set1_ps(-0.0f), a); }
  static M ge(F a, F b) { return _mm256_cmp_ps(a, b, _CMP_GE_OQ); }
  static M le(F a, F b) { return _mm256_cmp_ps(a, b, _CMP_LE_OQ); }
  static M gt(F a, F b) { return _mm256_cmp_ps(a, b, _CMP_GT_OQ); }
  static M lt(F a, F b) { return _mm256_cmp_ps(a, b, _CMP_LT_OQ); }
  static M both(M a, M b) { return _mm256_and_ps(a, b); }
  static M either(M a, M b) { return _mm256_or_ps(a, b); }
  static M not_(M a) { return _mm256_xor_ps(a, _mm256_castsi256_ps(_mm256_set1_epi32(-1))); }
  static M from_bits(std::uint32_t b) {
    const __m256i bit = _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128);
    return _mm256_castsi256_ps(_mm256_cmpeq_epi32(_mm256_and_si256(_mm256_set1_epi32(static_cast<int>(b)), bit), bit));
  }
  static F select(M m, F if_true, F if_false) { return _mm256_blendv_ps(if_false, if_true, m); }
  static F neg(F a) { return _mm256_xor_ps(a, _mm256_set1_ps(-0.0f)); }
  static void store(float* p, F a) { _mm256_store_ps(p, a); }
  static std::uint64_t bits(M m) { return static_cast<std::uint32_t>(_mm256_movemask_ps(m)); }
};
#elif EXAO_KERNEL_LANES == 4
using Lanes8 = LanesSse;
#endif
