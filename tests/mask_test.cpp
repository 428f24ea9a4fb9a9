// Mask<Bits>: the vectorised operations against their scalar twin, and the helpers around them.

#include <gtest/gtest.h>

#include <iostream>
#include <vector>

#include "core/mask.h"
#include "core/mask_set.h"
#include "core/random.h"

namespace exao {
namespace {

template <int Bits>
Mask<Bits> random_mask(Rng& rng, int n) {
  Mask<Bits> m;
  // Mix dense, sparse and empty words so popcount and any() see every case.
  for (auto& w : m.words) {
    switch (rng.below(4)) {
      case 0: w = 0; break;
      case 1: w = rng.next(); break;
      case 2: w = rng.next() & rng.next() & rng.next(); break;
      default: w = ~std::uint64_t{0}; break;
    }
  }
  return m & Mask<Bits>::ones(n);
}

template <class T>
class MaskTest : public ::testing::Test {};
using Widths = ::testing::Types<std::integral_constant<int, 64>, std::integral_constant<int, 128>,
                                std::integral_constant<int, 256>, std::integral_constant<int, 512>,
                                std::integral_constant<int, 1024>>;
TYPED_TEST_SUITE(MaskTest, Widths);

TYPED_TEST(MaskTest, VectorOpsEqualScalarTwin) {
  constexpr int Bits = TypeParam::value;
  Rng rng(Bits);
  for (int trial = 0; trial < 2000; ++trial) {
    const int n = 32 * (1 + static_cast<int>(rng.below(Bits / 32)));
    const Mask<Bits> a = random_mask<Bits>(rng, n), b = random_mask<Bits>(rng, n);
    EXPECT_EQ(a | b, scalar::or_(a, b));
    EXPECT_EQ(a & b, scalar::and_(a, b));
    EXPECT_EQ(and_not(a, b), scalar::and_not(a, b));
    Mask<Bits> c = a;
    c |= b;
    EXPECT_EQ(c, scalar::or_(a, b));
    c = a;
    c &= b;
    EXPECT_EQ(c, scalar::and_(a, b));
    EXPECT_EQ(a.popcount(), scalar::popcount(a));
    EXPECT_EQ(a.any(), scalar::any(a));
    EXPECT_EQ(a.none(), !scalar::any(a));
    EXPECT_EQ(popcount_and_not(a, b), scalar::popcount_and_not(a, b));
    // Bits at or beyond n stay zero through every operation.
    EXPECT_EQ(and_not(a | b, Mask<Bits>::ones(n)).popcount(), 0);
  }
}

TYPED_TEST(MaskTest, SingleBitsAndOnes) {
  constexpr int Bits = TypeParam::value;
  Mask<Bits> m;
  EXPECT_TRUE(m.none());
  EXPECT_EQ(m.popcount(), 0);
  for (int i = 0; i < Bits; i += 7) {
    Mask<Bits> one;
    one.set(i);
    EXPECT_TRUE(one.test(i));
    EXPECT_TRUE(one.any());
    EXPECT_EQ(one.popcount(), 1);
    if (i > 0) {
      EXPECT_FALSE(one.test(i - 1));
    }
    m |= one;
  }
  EXPECT_EQ(m.popcount(), (Bits - 1) / 7 + 1);
  for (int n = 0; n <= Bits; n += 32) {
    const Mask<Bits> ones = Mask<Bits>::ones(n);
    EXPECT_EQ(ones.popcount(), n);
    if (n > 0) {
      EXPECT_TRUE(ones.test(n - 1));
    }
    if (n < Bits) {
      EXPECT_FALSE(ones.test(n));
    }
  }
  EXPECT_EQ(Mask<Bits>::ones(Bits).popcount(), Bits);
  EXPECT_EQ(and_not(Mask<Bits>::ones(Bits), Mask<Bits>::ones(Bits)).popcount(), 0);
  EXPECT_EQ(alignof(Mask<Bits>), kMaskAlign<Bits>);
  EXPECT_EQ(sizeof(Mask<Bits>), static_cast<std::size_t>(Bits / 8));
}

TEST(WithMaskBits, PicksTheSmallestWidth) {
  const auto width = [](int samples) {
    return with_mask_bits(samples, [](auto bits) { return decltype(bits)::value; });
  };
  EXPECT_EQ(width(32), 64);
  EXPECT_EQ(width(64), 64);
  EXPECT_EQ(width(96), 128);
  EXPECT_EQ(width(128), 128);
  EXPECT_EQ(width(160), 256);
  EXPECT_EQ(width(256), 256);
  EXPECT_EQ(width(288), 512);
  EXPECT_EQ(width(512), 512);
  EXPECT_EQ(width(544), 1024);
  EXPECT_EQ(width(1024), 1024);
}

TEST(MaskStore, WritesAMaskSetRow) {
  for (const int samples : {32, 96, 160, 1024}) {
    with_mask_bits(samples, [&](auto bits) {
      constexpr int Bits = decltype(bits)::value;
      Rng rng(static_cast<std::uint64_t>(samples));
      MaskSet set(3, samples);
      const Mask<Bits> m = random_mask<Bits>(rng, samples);
      store(m, set.row(1));
      EXPECT_EQ(set.blocked_count(0), 0);
      EXPECT_EQ(set.blocked_count(2), 0);
      EXPECT_EQ(set.blocked_count(1), m.popcount());
      for (int i = 0; i < samples; ++i) EXPECT_EQ(set.blocked(1, i), m.test(i));
      EXPECT_EQ(load_mask<Bits>(set.row(1)), m);
    });
  }
}

TEST(Simd, ReportsTheInstructionSet) {
  RecordProperty("simd", simd_name());
  std::cout << "mask kernels compiled for: " << simd_name() << "\n";
}

}  // namespace
}  // namespace exao
