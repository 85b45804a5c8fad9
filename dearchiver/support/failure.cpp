#include "failure.hpp"

#include <string>
#include <utility>

namespace statepack::detail {

Error failure(ErrorCode code, std::string message, VkResult vk_result) {
  return Error{code, std::move(message), vk_result};
}

Error corrupt(std::string message) {
  return failure(ErrorCode::corrupt, "corrupt archive: " + std::move(message));
}

Error out_of_memory_in(const char* entry_point) noexcept {
  try {
    return Error{ErrorCode::out_of_memory, std::string(entry_point) + ": out of memory"};
  } catch (...) {
    return Error{ErrorCode::out_of_memory, "out of memory"};  // (a short string needs no allocation)
  }
}

Error unexpected_exception_in(const char* entry_point, const char* what) noexcept {
  try {
    return Error{ErrorCode::invalid_argument, std::string(entry_point) + ": unexpected exception" +
                                                  (what ? std::string(": ") + what : std::string())};
  } catch (...) {
    return Error{ErrorCode::out_of_memory, "out of memory"};
  }
}

}  // namespace statepack::detail
