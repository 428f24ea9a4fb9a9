// core/check.h: a failed check prints the expression and the values involved, and stays on in
// Release builds.

#include <gtest/gtest.h>

#include <cstdint>

#include "core/check.h"

namespace exao {
namespace {

TEST(Check, PassingChecksDoNothing) {
  const int a = 3;
  const std::size_t b = 4;
  EXAO_CHECK(a == 3);
  EXAO_CHECK_EQ(a, 3);
  EXAO_CHECK_NE(a, 4);
  EXAO_CHECK_LT(a, b);
  EXAO_CHECK_LE(b, 4u);
  EXAO_CHECK_GT(b, a);
  EXAO_CHECK_GE(a, 3);
  EXAO_DCHECK_LT(a, b);
  SUCCEED();
}

TEST(CheckDeathTest, FailuresPrintTheValues) {
  const int count = 7;
  const int limit = 5;
  EXPECT_DEATH(EXAO_CHECK_LT(count, limit), "check failed: count < limit with count = 7, limit = 5");
  EXPECT_DEATH(EXAO_CHECK_EQ(count, 8), "count == 8 with count = 7, 8 = 8");
  EXPECT_DEATH(EXAO_CHECK(count == limit), "check failed: count == limit");
}

TEST(CheckDeathTest, SignednessDoesNotHideAFailure) {
  // -1 < 1u is false in plain C++ (-1 becomes a huge unsigned value); the check compares values.
  const int negative = -1;
  const unsigned one = 1;
  EXAO_CHECK_LT(negative, one);
  EXPECT_DEATH(EXAO_CHECK_GT(negative, one), "negative > one with negative = -1, one = 1");
}

}  // namespace
}  // namespace exao
