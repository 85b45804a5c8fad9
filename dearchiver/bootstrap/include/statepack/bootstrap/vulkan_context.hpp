// A minimal Vulkan instance + device for the samples and tests: validation layers with a messenger
// that records every warning and error, lavapipe selectable by driver ID, one graphics+compute queue.
#pragma once

#include <vulkan/vulkan.h>

#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "statepack/dearchiver.hpp"
#include "statepack/result.hpp"

namespace statepack::bootstrap {

// A Vulkan structure zeroed but for its sType. `T x{type}` would say the same, but -Wextra
// (missing-field-initializers) warns on it in every program that includes this header.
template <class T>
constexpr T vk_structure(VkStructureType type) {
  T s{};
  s.sType = type;
  return s;
}

// How validation_messages() begins a performance warning of the layer (advice about speed, such as an
// output no later stage reads). Every other message begins "validation error: " or "validation warning: ".
inline constexpr char kPerformanceWarning[] = "validation performance warning: ";

struct VulkanContextOptions {
  bool validation = true;              // enable VK_LAYER_KHRONOS_validation (an error when it is missing)
  bool validation_if_present = false;  // with validation: enable it only when installed, no error
  bool require_lavapipe = false;       // only accept Mesa's CPU driver (tests: same results everywhere)
  int device_index = -1;  // >= 0: that entry of vkEnumeratePhysicalDevices, else the first 1.3 one
  bool enable_supported_features = false;        // enable every core 1.0-1.3 feature the device supports
  std::vector<const char*> instance_extensions;  // e.g. what GLFW needs
  // The device's host allocator (vkCreateDevice's pAllocator, kept until the device is destroyed): the
  // driver allocates objects made on the device through it.
  const VkAllocationCallbacks* device_allocator = nullptr;
  // With validation: also the layer's synchronization validation (missing or wrong barriers, hazards
  // between submissions), reported like every other message.
  bool synchronization_validation = true;
};

class VulkanContext {
 public:
  static Result<std::unique_ptr<VulkanContext>> create(const VulkanContextOptions& options);
  ~VulkanContext();
  VulkanContext(const VulkanContext&) = delete;
  VulkanContext& operator=(const VulkanContext&) = delete;

  VkInstance instance = VK_NULL_HANDLE;
  VkPhysicalDevice physical_device = VK_NULL_HANDLE;
  VkDevice device = VK_NULL_HANDLE;
  VkQueue queue = VK_NULL_HANDLE;
  uint32_t queue_family = 0;
  VkCommandPool command_pool = VK_NULL_HANDLE;
  std::string device_name;
  std::string driver_name;
  bool validation_enabled = false;
  VkPhysicalDeviceFeatures enabled_features{};  // what the device was created with
  // ... every structure of it, chained as given to vkCreateDevice (enabled_features2 heads the chain)
  VkPhysicalDeviceFeatures2 enabled_features2 =
      vk_structure<VkPhysicalDeviceFeatures2>(VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2);
  VkPhysicalDeviceVulkan11Features enabled_features11 =
      vk_structure<VkPhysicalDeviceVulkan11Features>(VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_1_FEATURES);
  VkPhysicalDeviceVulkan12Features enabled_features12 =
      vk_structure<VkPhysicalDeviceVulkan12Features>(VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES);
  VkPhysicalDeviceVulkan13Features enabled_features13 =
      vk_structure<VkPhysicalDeviceVulkan13Features>(VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES);
  std::vector<const char*> enabled_extensions;              // device extensions
  const VkAllocationCallbacks* device_allocator = nullptr;  // as created with

  // The Dearchiver's view of this device: its handles, the features it was created with, and this
  // context's loader as the dispatch (as an engine hands over its own).
  DeviceContext device_context() const;

  // Destroys the device while the messenger still listens, so objects left alive are reported
  // (tests call this before checking validation_messages()).
  void destroy_device();

  // Every validation warning or error so far (empty when validation is off).
  std::vector<std::string> validation_messages() const;

  // Records commands into a fresh command buffer, submits them and waits.
  Result<void> submit_and_wait(const std::function<void(VkCommandBuffer)>& record);

  // A memory type index with `required` properties among `type_bits`, or UINT32_MAX.
  uint32_t find_memory_type(uint32_t type_bits, VkMemoryPropertyFlags required) const;

 private:
  VulkanContext() = default;
  // The steps of create(), in order.
  Result<void> create_instance(const VulkanContextOptions& options);
  Result<void> choose_physical_device(const VulkanContextOptions& options);
  Result<void> create_device(const VulkanContextOptions& options);
  void* chain_capability_extensions();
  // With enable_supported_features: the extensions that allow SPIR-V capabilities and their features.
  std::vector<const char*> capability_extension_names_;
  std::vector<std::vector<unsigned char>> capability_extension_features_;
  static VKAPI_ATTR VkBool32 VKAPI_CALL on_message(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                                   VkDebugUtilsMessageTypeFlagsEXT types,
                                                   const VkDebugUtilsMessengerCallbackDataEXT* data,
                                                   void* self);
  VkDebugUtilsMessengerEXT messenger_ = VK_NULL_HANDLE;
  mutable std::mutex mutex_;
  std::vector<std::string> messages_;
};

// A host-visible buffer with its memory, freed on destruction.
struct HostBuffer {
  VkDevice device = VK_NULL_HANDLE;
  VkBuffer buffer = VK_NULL_HANDLE;
  VkDeviceMemory memory = VK_NULL_HANDLE;
  void* mapped = nullptr;
  VkDeviceSize size = 0;
  ~HostBuffer();
};
Result<std::unique_ptr<HostBuffer>> create_host_buffer(VulkanContext& vk, VkDeviceSize size,
                                                       VkBufferUsageFlags usage);

// A device-local 2D image with a view (of every aspect of its format) and its memory, freed on destruction.
struct DeviceImage {
  VkDevice device = VK_NULL_HANDLE;
  VkImage image = VK_NULL_HANDLE;
  VkImageView view = VK_NULL_HANDLE;
  VkDeviceMemory memory = VK_NULL_HANDLE;
  ~DeviceImage();
};
Result<std::unique_ptr<DeviceImage>> create_device_image(VulkanContext& vk, VkFormat format, uint32_t width,
                                                         uint32_t height, VkImageUsageFlags usage);

// The aspects of a format's images: depth and/or stencil for depth-stencil formats, else color.
VkImageAspectFlags format_aspects(VkFormat format);

// One image layout transition with its memory dependency (the whole image, of the given aspects).
void image_barrier(VkCommandBuffer cmd, VkImage image, VkImageLayout from, VkImageLayout to,
                   VkAccessFlags src_access, VkAccessFlags dst_access, VkPipelineStageFlags src_stage,
                   VkPipelineStageFlags dst_stage, VkImageAspectFlags aspects = VK_IMAGE_ASPECT_COLOR_BIT);

// A descriptor pool with one set that binds one storage buffer; both freed on destruction.
struct StorageBufferSet {
  VkDevice device = VK_NULL_HANDLE;
  VkDescriptorPool pool = VK_NULL_HANDLE;
  VkDescriptorSet set = VK_NULL_HANDLE;
  ~StorageBufferSet();
};
Result<std::unique_ptr<StorageBufferSet>> bind_storage_buffer(VulkanContext& vk, VkDescriptorSetLayout layout,
                                                              uint32_t binding, VkBuffer buffer);

}  // namespace statepack::bootstrap
