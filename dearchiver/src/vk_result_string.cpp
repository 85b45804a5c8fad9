#include "vk_result_string.hpp"

#include <vulkan/vulkan.hpp>  // brings vk::to_string

namespace statepack {

// Uses Vulkan-Hpp's generated names ("ErrorOutOfDeviceMemory") so new codes need no upkeep here.
std::string vk_result_string(VkResult result) {
  return "VkResult " + vk::to_string(static_cast<vk::Result>(result)) + " (" +
         std::to_string(static_cast<int>(result)) + ")";
}

}  // namespace statepack
