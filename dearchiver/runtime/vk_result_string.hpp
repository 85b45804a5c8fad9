// Names of VkResult values for error messages, and the error of a failed Vulkan call.
#pragma once

#include <vulkan/vulkan.h>

#include <string>
#include <string_view>

#include "statepack/result.hpp"

namespace statepack::detail {
std::string vk_result_string(VkResult result);
// A vulkan_error naming the call, the object and the result, which Error::vk_result also carries.
[[gnu::cold]] Error vulkan_failure(const char* call, VkResult result, std::string_view object);
}  // namespace statepack::detail
