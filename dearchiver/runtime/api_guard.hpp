// No exception crosses the library boundary: every public entry point runs its body through
// api_guard, which turns what the standard library may throw (std::bad_alloc above all, and whatever
// a caller's modify callback throws) into an Error.
#pragma once

#include <exception>
#include <new>
#include <string>

#include "statepack/result.hpp"
#include "support/failure.hpp"

namespace statepack::detail {

template <class F>
auto api_guard(const char* entry_point, F&& body) noexcept -> decltype(body()) {
  try {
    return body();
  } catch (const std::bad_alloc&) {
    return out_of_memory_in(entry_point);
  } catch (const std::exception& e) {
    return unexpected_exception_in(entry_point, e.what());
  } catch (...) {
    return unexpected_exception_in(entry_point, nullptr);
  }
}

}  // namespace statepack::detail
