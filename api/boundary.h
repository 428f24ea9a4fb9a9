#pragma once
// exao::api::detail: the API boundary. Every public function runs its body through guard(),
// which turns any exception (std::bad_alloc, an exception from TBB or a caller's callback) into
// a returned Error, so nothing is thrown across the boundary, printed, or fatal.

#include <exception>
#include <new>
#include <string>
#include <utility>

#include "core/error.h"
#include "exao/exao.hpp"

namespace exao::api::detail {

[[nodiscard]] inline Error make_error(StatusCode code, std::string message) { return Error{code, std::move(message)}; }
[[nodiscard]] inline Error invalid(std::string message) { return make_error(StatusCode::InvalidArgument, std::move(message)); }
/// An internal module's error (exao::Error, from core/lut/bvh) with the code the caller sees.
[[nodiscard]] inline Error from_internal(StatusCode code, const exao::Error& error) { return make_error(code, error.message); }

/// Runs body() -> R (a Result<T> or Status), turning exceptions into errors. Building an Error
/// can itself throw std::bad_alloc (its message is a std::string): the fallbacks then carry an
/// empty message, which cannot allocate.
template <class R, class Body>
[[nodiscard]] R guard(Body&& body) noexcept {
  try {
    return std::forward<Body>(body)();
  } catch (const std::bad_alloc&) {
    try {
      return R(make_error(StatusCode::OutOfMemory, "out of memory"));
    } catch (...) {
      return R(Error{StatusCode::OutOfMemory, {}});
    }
  } catch (const std::exception& e) {
    try {
      return R(make_error(StatusCode::InternalError, std::string("unexpected exception: ") + e.what()));
    } catch (...) {
      return R(Error{StatusCode::InternalError, {}});
    }
  } catch (...) {
    return R(Error{StatusCode::InternalError, {}});
  }
}

}  // namespace exao::api::detail
