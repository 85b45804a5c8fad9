// The Vulkan entry points the runtime calls, loaded once from the application's own dispatch
// (DeviceContext::get_instance_proc_addr, as volk or an engine's table provide it) or, when it gives
// none, from the system's loader opened at run time. The runtime is compiled with VK_NO_PROTOTYPES, so
// no call can reach Vulkan by symbol and the library never links libvulkan.
#pragma once

#include "statepack/dearchiver.hpp"

namespace statepack::detail {

// X(name) for each function, instance-level first: one list for the members and for the loader.
#define STATEPACK_VK_INSTANCE_FUNCTIONS(X) \
  X(vkGetPhysicalDeviceProperties)         \
  X(vkGetPhysicalDeviceFeatures)           \
  X(vkGetPhysicalDeviceFormatProperties)   \
  X(vkGetDeviceProcAddr)
#define STATEPACK_VK_DEVICE_FUNCTIONS(X) \
  X(vkCreateShaderModule)                \
  X(vkDestroyShaderModule)               \
  X(vkCreateDescriptorSetLayout)         \
  X(vkDestroyDescriptorSetLayout)        \
  X(vkCreateSampler)                     \
  X(vkDestroySampler)                    \
  X(vkCreateRenderPass)                  \
  X(vkDestroyRenderPass)                 \
  X(vkCreatePipelineLayout)              \
  X(vkDestroyPipelineLayout)             \
  X(vkCreateGraphicsPipelines)           \
  X(vkCreateComputePipelines)            \
  X(vkDestroyPipeline)                   \
  X(vkCreatePipelineCache)               \
  X(vkGetPipelineCacheData)

struct VulkanFunctions {
#define STATEPACK_VK_MEMBER(name) PFN_##name name = nullptr;
  STATEPACK_VK_INSTANCE_FUNCTIONS(STATEPACK_VK_MEMBER)
  STATEPACK_VK_DEVICE_FUNCTIONS(STATEPACK_VK_MEMBER)
#undef STATEPACK_VK_MEMBER
  // Vulkan 1.1: null on an older instance (the pipeline cache's identity then omits the driver fields).
  PFN_vkGetPhysicalDeviceProperties2 vkGetPhysicalDeviceProperties2 = nullptr;
  PFN_vkGetPhysicalDeviceFeatures2 vkGetPhysicalDeviceFeatures2 = nullptr;  // the same
};

// Every function of the lists above, or an invalid_argument / not_found error naming `caller`, the
// missing function and what to pass instead.
Result<VulkanFunctions> load_vulkan_functions(const DeviceContext& context, const char* caller);

// The Vulkan version the library may use on `context`'s device: the lower of the device's and the
// application's (DeviceContext::api_version, when given).
inline uint32_t effective_api_version(const DeviceContext& context, uint32_t device_version) {
  return context.api_version != 0 && context.api_version < device_version ? context.api_version
                                                                          : device_version;
}

}  // namespace statepack::detail
