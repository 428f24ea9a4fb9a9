#pragma once
// Checks of a programmer's mistake (STYLE.md, the first tier of failure), in the spirit of
// pbrt's CHECK_EQ: a failed check prints the file, the line, the expression and the values
// involved, then aborts. They are never for bad input, which is a returned Error.
//
//  - EXAO_CHECK, EXAO_CHECK_EQ/NE/LT/LE/GT/GE stay on in every build type (Release is what users
//    and CI run): use them where the check is cheap next to the work around it.
//  - EXAO_DCHECK... are for hot loops: on in Debug builds (no NDEBUG) or with EXAO_DEBUG_CHECKS,
//    compiled away otherwise (the expression is not evaluated, but still type-checked).

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>
#include <type_traits>
#include <utility>

namespace exao::detail {

[[noreturn, gnu::cold, gnu::noinline]] inline void check_failed(const char* file, int line, const char* expression,
                                                               const std::string& values) {
  std::fprintf(stderr, "%s:%d: check failed: %s%s%s\n", file, line, expression, values.empty() ? "" : " with ",
               values.c_str());
  std::fflush(stderr);
  std::abort();
}

template <class A, class B>
[[nodiscard, gnu::cold]] std::string check_values(const char* a_text, const A& a, const char* b_text, const B& b) {
  std::ostringstream out;
  const auto put = [&out](const auto& v) {
    if constexpr (std::is_same_v<std::decay_t<decltype(v)>, std::uint8_t> ||
                  std::is_same_v<std::decay_t<decltype(v)>, std::int8_t>) {
      out << static_cast<int>(v);
    } else if constexpr (std::is_enum_v<std::decay_t<decltype(v)>>) {
      out << static_cast<long long>(v);
    } else {
      out << v;
    }
  };
  out << a_text << " = ";
  put(a);
  out << ", " << b_text << " = ";
  put(b);
  return out.str();
}

// Integer comparisons are exact across signedness (std::cmp_*), so that a check never passes
// because -1 became a huge unsigned number.
#define EXAO_DETAIL_COMPARE(name, op, cmp)                                                   \
  template <class A, class B>                                                                \
  [[nodiscard]] constexpr bool name(const A& a, const B& b) {                                \
    if constexpr (std::is_integral_v<A> && std::is_integral_v<B> && !std::is_same_v<A, bool> && \
                  !std::is_same_v<B, bool>) {                                                \
      return cmp(a, b);                                                                      \
    } else {                                                                                 \
      return a op b;                                                                         \
    }                                                                                        \
  }
EXAO_DETAIL_COMPARE(check_eq, ==, std::cmp_equal)
EXAO_DETAIL_COMPARE(check_ne, !=, std::cmp_not_equal)
EXAO_DETAIL_COMPARE(check_lt, <, std::cmp_less)
EXAO_DETAIL_COMPARE(check_le, <=, std::cmp_less_equal)
EXAO_DETAIL_COMPARE(check_gt, >, std::cmp_greater)
EXAO_DETAIL_COMPARE(check_ge, >=, std::cmp_greater_equal)
#undef EXAO_DETAIL_COMPARE

}  // namespace exao::detail

#define EXAO_CHECK(condition)                                                          \
  do {                                                                                 \
    if (!(condition)) [[unlikely]] {                                                   \
      ::exao::detail::check_failed(__FILE__, __LINE__, #condition, std::string());     \
    }                                                                                  \
  } while (false)

#define EXAO_DETAIL_CHECK_OP(compare, op, a, b)                                                      \
  do {                                                                                               \
    const auto& exao_check_a_ = (a);                                                                 \
    const auto& exao_check_b_ = (b);                                                                 \
    if (!::exao::detail::compare(exao_check_a_, exao_check_b_)) [[unlikely]] {                       \
      ::exao::detail::check_failed(__FILE__, __LINE__, #a " " #op " " #b,                            \
                                   ::exao::detail::check_values(#a, exao_check_a_, #b, exao_check_b_)); \
    }                                                                                                \
  } while (false)

#define EXAO_CHECK_EQ(a, b) EXAO_DETAIL_CHECK_OP(check_eq, ==, a, b)
#define EXAO_CHECK_NE(a, b) EXAO_DETAIL_CHECK_OP(check_ne, !=, a, b)
#define EXAO_CHECK_LT(a, b) EXAO_DETAIL_CHECK_OP(check_lt, <, a, b)
#define EXAO_CHECK_LE(a, b) EXAO_DETAIL_CHECK_OP(check_le, <=, a, b)
#define EXAO_CHECK_GT(a, b) EXAO_DETAIL_CHECK_OP(check_gt, >, a, b)
#define EXAO_CHECK_GE(a, b) EXAO_DETAIL_CHECK_OP(check_ge, >=, a, b)

#if !defined(NDEBUG) || defined(EXAO_DEBUG_CHECKS)
#define EXAO_DCHECK(condition) EXAO_CHECK(condition)
#define EXAO_DCHECK_EQ(a, b) EXAO_CHECK_EQ(a, b)
#define EXAO_DCHECK_LT(a, b) EXAO_CHECK_LT(a, b)
#define EXAO_DCHECK_LE(a, b) EXAO_CHECK_LE(a, b)
#else
// sizeof keeps the expression type-checked without evaluating it.
#define EXAO_DCHECK(condition) static_cast<void>(sizeof(static_cast<bool>(condition)))
#define EXAO_DCHECK_EQ(a, b) static_cast<void>(sizeof((a) == (b)))
#define EXAO_DCHECK_LT(a, b) static_cast<void>(sizeof((a) < (b)))
#define EXAO_DCHECK_LE(a, b) static_cast<void>(sizeof((a) <= (b)))
#endif
