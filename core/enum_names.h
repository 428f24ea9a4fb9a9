#pragma once
// exao::name_of, parse_enum and all_names: one mechanism for the names of the library's enums
// (option values such as "bvh", "packet16", "avx2", and names in files such as "points").
//
// Each enum has one table of {value, name} pairs, a constexpr function `enum_names(E)` declared
// beside the enum in its own namespace (found by argument-dependent lookup), in the order its
// lists are written for users ("auto, embree, brute, bvh or raster"):
//
//   enum class Falloff { Constant, Linear, Quadratic };
//   [[nodiscard]] constexpr auto enum_names(Falloff) {
//     return std::to_array<EnumName<Falloff>>({{Falloff::Constant, "constant"}, ...});
//   }
//
// Names are string literals, unique within their enum; tests/enum_names_test.cpp checks every
// table (unique names, name -> value -> name).

#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

namespace exao {

template <class E>
struct EnumName {
  E value;
  const char* name;  // a string literal
};

/// An enum with a table of names (an `enum_names(E)` found by argument-dependent lookup).
template <class E>
concept NamedEnum = requires { enum_names(E{}); };

/// The value's name; "?" for a value the table does not hold (a cast from a bad number).
template <NamedEnum E>
[[nodiscard]] constexpr const char* name_of(E value) {
  for (const EnumName<E>& entry : enum_names(E{})) {
    if (entry.value == value) return entry.name;
  }
  return "?";
}

/// The value named `text` (exactly, case and all); nullopt for any other text.
template <NamedEnum E>
[[nodiscard]] constexpr std::optional<E> parse_enum(std::string_view text) {
  for (const EnumName<E>& entry : enum_names(E{})) {
    if (text == entry.name) return entry.value;
  }
  return std::nullopt;
}

/// Every value, in the table's order.
template <NamedEnum E>
[[nodiscard]] constexpr auto all_values() {
  constexpr auto table = enum_names(E{});
  std::array<E, table.size()> out{};
  for (std::size_t i = 0; i < table.size(); ++i) out[i] = table[i].value;
  return out;
}

/// Every name, in the table's order.
template <NamedEnum E>
[[nodiscard]] constexpr auto all_names() {
  constexpr auto table = enum_names(E{});
  std::array<std::string_view, table.size()> out{};
  for (std::size_t i = 0; i < table.size(); ++i) out[i] = table[i].name;
  return out;
}

/// The names as a list for messages: "lut or exact", "single, packet4, packet8 or packet16"
/// (`last` joins the last two; ", " gives a plain comma-separated list).
template <NamedEnum E>
[[nodiscard]] std::string name_list(std::string_view last = " or ") {
  std::string out;
  const auto names = all_names<E>();
  for (std::size_t i = 0; i < names.size(); ++i) {
    if (i > 0) out += i + 1 == names.size() ? last : std::string_view(", ");
    out += names[i];
  }
  return out;
}

}  // namespace exao
