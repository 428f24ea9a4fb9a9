#pragma once
// exao::StreamCursor: numbers and words taken from text exactly as a std::istream in the "C"
// locale takes them with libstdc++ 12 (`>> std::string`, `>> double`, `>> float`, `>> int`), for
// the ASCII fast paths (io/obj_ascii_reader.h, io/ply_ascii_reader.h), which must read what CGAL's
// stream-based readers read, bit for bit. Internal to io/.

#include <charconv>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string_view>
#include <system_error>

namespace exao {

/// What a std::istream skips before a value (isspace in the "C" locale).
[[nodiscard]] constexpr bool is_stream_space(char c) {
  return c == ' ' || c == '\t' || c == '\n' || c == '\v' || c == '\f' || c == '\r';
}

struct StreamCursor {
  const char* p;
  const char* end;

  void skip_space() {
    while (p != end && is_stream_space(*p)) ++p;
  }

  /// The next word (what `>> std::string` reads); empty at the end.
  [[nodiscard]] std::string_view word() {
    skip_space();
    const char* start = p;
    while (p != end && !is_stream_space(*p)) ++p;
    return {start, static_cast<std::size_t>(p - start)};
  }

  /// `>> double` or `>> float`: num_get::_M_extract_float collects a sign, digits, one '.', and an
  /// 'e' (only after a digit) with its own sign and digits; strtod (strtof) must then take every
  /// character collected, and an infinite result fails. false where the stream would fail. The
  /// value is read by std::from_chars, which rounds as strtod does (correctly, to nearest; in
  /// libstdc++ 12 it runs fast_float's algorithm, as fast as the fast_float headers), from the
  /// same characters, a leading '+' (which strtod takes and from_chars does not) skipped.
  template <class Real>
  [[nodiscard]] bool number(Real& out) {
    skip_space();
    if (p == end) return false;
    const char* start = p;
    if (*p == '+' || *p == '-') ++p;
    bool mantissa = false;
    bool dot = false;
    bool exponent = false;
    while (p != end) {
      const char c = *p;
      if (c >= '0' && c <= '9') {
        mantissa = true;
      } else if (c == '.' && !dot && !exponent) {
        dot = true;
      } else if ((c == 'e' || c == 'E') && !exponent && mantissa) {
        exponent = true;
        if (++p == end) break;
        if (*p != '+' && *p != '-') continue;  // the character after 'e' is looked at again
      } else {
        break;
      }
      ++p;
    }
    const char* first = *start == '+' ? start + 1 : start;
    if (first == p) return false;
    const std::from_chars_result r = std::from_chars(first, p, out);
    return r.ec == std::errc() && r.ptr == p && !std::isinf(out);
  }

  /// `>> int`: a sign and decimal digits; false where the stream fails (no digit, or beyond int).
  /// The cursor stays where it was on failure.
  [[nodiscard]] bool integer(long long& out) {
    skip_space();
    const char* start = p;
    bool negative = false;
    if (p != end && (*p == '+' || *p == '-')) negative = *p++ == '-';
    const long long limit =
        negative ? -static_cast<long long>(std::numeric_limits<int>::min()) : std::numeric_limits<int>::max();
    long long value = 0;
    bool overflow = false;
    const char* digits = p;
    for (; p != end && *p >= '0' && *p <= '9'; ++p) {
      if (!overflow) value = value * 10 + (*p - '0');
      overflow = overflow || value > limit;
    }
    if (p == digits || overflow) {
      p = start;
      return false;
    }
    out = negative ? -value : value;
    return true;
  }

  /// Decimal digits alone, at most `max` (below 2^60): what every integer `>>` reads alike, signed or not, of
  /// any width that holds `max`. false for anything else (a sign, no digit, more than `max`),
  /// where the caller lets the stream-based reader decide.
  [[nodiscard]] bool digits(std::uint64_t& out, std::uint64_t max) {
    skip_space();
    const char* start = p;
    std::uint64_t value = 0;
    for (; p != end && *p >= '0' && *p <= '9'; ++p) {
      value = value * 10 + static_cast<std::uint64_t>(*p - '0');
      if (value > max) return false;
    }
    out = value;
    return p != start;
  }

  /// istream::ignore(256, ' '): up to 256 characters, through the first space.
  void ignore_through_space() {
    for (int n = 0; n < 256 && p != end; ++n) {
      if (*p++ == ' ') return;
    }
  }
};

}  // namespace exao
