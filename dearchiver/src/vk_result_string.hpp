// Names of VkResult values for error messages.
#pragma once

#include <vulkan/vulkan.h>

#include <string>

namespace statepack {
std::string vk_result_string(VkResult result);
}
