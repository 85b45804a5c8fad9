#include "failure.hpp"

#include <utility>

namespace statepack::detail {

Error failure(ErrorCode code, std::string message, VkResult vk_result) {
  return Error{code, std::move(message), vk_result};
}

Error corrupt(std::string message) {
  return failure(ErrorCode::corrupt, "corrupt archive: " + std::move(message));
}

}  // namespace statepack::detail
