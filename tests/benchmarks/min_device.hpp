// The device setup both minimal programs share, as an application writes its own: an instance, the
// first physical device with a compute queue, a device with that queue, nothing enabled. (The bootstrap
// library the samples use chooses devices, records validation messages and enables extensions: more
// than these programs need, and not what an application ships.) Also a terminal-safe copy of a message.
#pragma once

#include <vulkan/vulkan.h>

#include <cstdio>
#include <string>
#include <string_view>
#include <vector>

namespace min_device {

struct Device {
  VkInstance instance = VK_NULL_HANDLE;
  VkPhysicalDevice physical_device = VK_NULL_HANDLE;
  VkDevice device = VK_NULL_HANDLE;
  ~Device() {
    if (device) vkDestroyDevice(device, nullptr);
    if (instance) vkDestroyInstance(instance, nullptr);
  }
};

// False when no device has a compute queue, or a call fails.
inline bool create(Device& out) {
  VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
  app.apiVersion = VK_API_VERSION_1_0;
  VkInstanceCreateInfo instance_info{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
  instance_info.pApplicationInfo = &app;
  if (vkCreateInstance(&instance_info, nullptr, &out.instance) != VK_SUCCESS) return false;
  uint32_t count = 0;
  vkEnumeratePhysicalDevices(out.instance, &count, nullptr);
  std::vector<VkPhysicalDevice> devices(count);
  vkEnumeratePhysicalDevices(out.instance, &count, devices.data());
  for (VkPhysicalDevice physical : devices) {
    uint32_t families = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(physical, &families, nullptr);
    std::vector<VkQueueFamilyProperties> properties(families);
    vkGetPhysicalDeviceQueueFamilyProperties(physical, &families, properties.data());
    for (uint32_t family = 0; family < families; ++family) {
      if (!(properties[family].queueFlags & VK_QUEUE_COMPUTE_BIT)) continue;
      const float priority = 1.0f;
      VkDeviceQueueCreateInfo queue{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
      queue.queueFamilyIndex = family;
      queue.queueCount = 1;
      queue.pQueuePriorities = &priority;
      VkDeviceCreateInfo device_info{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
      device_info.queueCreateInfoCount = 1;
      device_info.pQueueCreateInfos = &queue;
      out.physical_device = physical;
      return vkCreateDevice(physical, &device_info, nullptr, &out.device) == VK_SUCCESS;
    }
  }
  return false;
}

// `text` with control bytes and bytes past ASCII as \xNN: a message may quote a name from a file.
inline std::string printable(std::string_view text) {
  std::string out;
  for (unsigned char c : text) {
    if (c >= 0x20 && c < 0x7F) {
      out += char(c);
    } else {
      char escaped[5];
      std::snprintf(escaped, sizeof escaped, "\\x%02X", c);
      out += escaped;
    }
  }
  return out;
}

}  // namespace min_device
