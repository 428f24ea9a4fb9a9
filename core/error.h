#pragma once
// Errors from bad input: returned, never thrown across module boundaries, printed once
// by the caller. The message is one line that names the file (or option) and the problem.

#include <expected>
#include <string>
#include <utility>

namespace exao {

struct Error {
  std::string message;
};

template <class T>
using Result = std::expected<T, Error>;

[[nodiscard]] inline std::unexpected<Error> fail(std::string message) {
  return std::unexpected<Error>(Error{std::move(message)});
}

}  // namespace exao
