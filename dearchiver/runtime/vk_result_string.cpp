#include "vk_result_string.hpp"

#include "support/failure.hpp"

#include <vulkan/vulkan.hpp>  // brings vk::to_string

namespace statepack::detail {

// Uses Vulkan-Hpp's generated names ("ErrorOutOfDeviceMemory") so new codes need no upkeep here.
std::string vk_result_string(VkResult result) {
  return "VkResult " + vk::to_string(static_cast<vk::Result>(result)) + " (" +
         std::to_string(static_cast<int>(result)) + ")";
}

Error vulkan_failure(const char* call, VkResult result, std::string_view object) {
  return detail::failure(
      ErrorCode::vulkan_error,
      std::string(call) + " failed for '" + std::string(object) + "': " + vk_result_string(result), result);
}

}  // namespace statepack::detail
