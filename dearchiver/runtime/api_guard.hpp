// No exception crosses the library boundary: every public entry point runs its body through
// api_guard, which turns what the standard library may throw (std::bad_alloc above all, and whatever
// a caller's modify callback throws) into an Error.
#pragma once

#include <exception>
#include <new>
#include <string>

#include "statepack/result.hpp"

namespace statepack::detail {

template <class F>
auto api_guard(const char* entry_point, F&& body) noexcept -> decltype(body()) {
  try {
    try {
      return body();
    } catch (const std::bad_alloc&) {
      return Error{ErrorCode::out_of_memory, std::string(entry_point) + ": out of memory"};
    } catch (const std::exception& e) {
      return Error{ErrorCode::invalid_argument,
                   std::string(entry_point) + ": unexpected exception: " + e.what()};
    } catch (...) {
      return Error{ErrorCode::invalid_argument, std::string(entry_point) + ": unexpected exception"};
    }
  } catch (...) {
    // Building the message itself failed (no memory left): a short string needs no allocation.
    return Error{ErrorCode::out_of_memory, "out of memory"};
  }
}

}  // namespace statepack::detail
