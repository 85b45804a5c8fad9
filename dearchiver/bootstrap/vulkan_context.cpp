#include "statepack/bootstrap/vulkan_context.hpp"

#include <cstring>
#include <set>
#include <string_view>

#include "runtime/spirv_capability_table.hpp"

namespace statepack::bootstrap {
namespace {

Error vk_error(const char* call, VkResult r) {
  return Error{ErrorCode::vulkan_error, std::string(call) + " failed with VkResult " + std::to_string(r), r};
}

bool has_layer(const char* name) {
  uint32_t count = 0;
  vkEnumerateInstanceLayerProperties(&count, nullptr);
  std::vector<VkLayerProperties> layers(count);
  vkEnumerateInstanceLayerProperties(&count, layers.data());
  for (const auto& l : layers)
    if (std::strcmp(l.layerName, name) == 0) return true;
  return false;
}

}  // namespace

VKAPI_ATTR VkBool32 VKAPI_CALL VulkanContext::on_message(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                                         VkDebugUtilsMessageTypeFlagsEXT types,
                                                         const VkDebugUtilsMessengerCallbackDataEXT* data,
                                                         void* self) {
  auto* ctx = static_cast<VulkanContext*>(self);
  // kPerformanceWarning marks advice about speed (an output no stage reads), not about validity.
  const bool error = severity & VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
  std::string text = error                                                       ? "validation error: "
                     : (types & VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT) ? kPerformanceWarning
                                                                                 : "validation warning: ";
  text += data->pMessage ? data->pMessage : "(no message)";
  std::lock_guard lock(ctx->mutex_);
  ctx->messages_.push_back(std::move(text));
  return VK_FALSE;
}

Result<std::unique_ptr<VulkanContext>> VulkanContext::create(const VulkanContextOptions& options) {
  std::unique_ptr<VulkanContext> ctx(new VulkanContext());
  if (auto r = ctx->create_instance(options); !r) return r.error();
  if (auto r = ctx->choose_physical_device(options); !r) return r.error();
  if (auto r = ctx->create_device(options); !r) return r.error();
  return ctx;
}

Result<void> VulkanContext::create_instance(const VulkanContextOptions& options) {
  constexpr const char* kValidationLayer = "VK_LAYER_KHRONOS_validation";
  const bool validation =
      options.validation && (!options.validation_if_present || has_layer(kValidationLayer));
  if (validation && !has_layer(kValidationLayer))
    return Error{ErrorCode::unsupported,
                 "the Vulkan validation layer is missing: apt-get install vulkan-validationlayers"};
  validation_enabled = validation;

  VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
  app.pApplicationName = "statepack";
  app.apiVersion = VK_API_VERSION_1_3;
  std::vector<const char*> extensions = options.instance_extensions;
  std::vector<const char*> layers;
  VkDebugUtilsMessengerCreateInfoEXT messenger_info{VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
  messenger_info.messageSeverity =
      VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
  messenger_info.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT |
                               VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                               VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
  messenger_info.pfnUserCallback = &VulkanContext::on_message;
  messenger_info.pUserData = this;
  VkInstanceCreateInfo instance_info{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
  const VkValidationFeatureEnableEXT synchronization =
      VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT;
  VkValidationFeaturesEXT features{VK_STRUCTURE_TYPE_VALIDATION_FEATURES_EXT};
  features.enabledValidationFeatureCount = 1;
  features.pEnabledValidationFeatures = &synchronization;
  if (validation) {
    layers.push_back(kValidationLayer);
    extensions.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
    instance_info.pNext = &messenger_info;  // also catches messages from instance creation itself
    if (options.synchronization_validation) {
      // The layer implements VK_EXT_validation_features itself.
      extensions.push_back(VK_EXT_VALIDATION_FEATURES_EXTENSION_NAME);
      features.pNext = &messenger_info;
      instance_info.pNext = &features;
    }
  }
  instance_info.pApplicationInfo = &app;
  instance_info.enabledLayerCount = static_cast<uint32_t>(layers.size());
  instance_info.ppEnabledLayerNames = layers.data();
  instance_info.enabledExtensionCount = static_cast<uint32_t>(extensions.size());
  instance_info.ppEnabledExtensionNames = extensions.data();
  if (VkResult r = vkCreateInstance(&instance_info, nullptr, &instance); r != VK_SUCCESS)
    return vk_error("vkCreateInstance", r);
  if (validation) {
    auto create_messenger = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(instance, "vkCreateDebugUtilsMessengerEXT"));
    if (VkResult r = create_messenger(instance, &messenger_info, nullptr, &messenger_); r != VK_SUCCESS)
      return vk_error("vkCreateDebugUtilsMessengerEXT", r);
  }
  return {};
}

Result<void> VulkanContext::choose_physical_device(const VulkanContextOptions& options) {
  uint32_t count = 0;
  vkEnumeratePhysicalDevices(instance, &count, nullptr);
  std::vector<VkPhysicalDevice> devices(count);
  vkEnumeratePhysicalDevices(instance, &count, devices.data());
  std::string seen;
  if (options.device_index >= 0 && size_t(options.device_index) >= devices.size())
    return Error{ErrorCode::unsupported, "there is no Vulkan device " + std::to_string(options.device_index) +
                                             " (this machine has " + std::to_string(devices.size()) + ")"};
  for (size_t index = 0; index < devices.size(); ++index) {
    VkPhysicalDevice pd = devices[index];
    VkPhysicalDeviceDriverProperties driver{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DRIVER_PROPERTIES};
    VkPhysicalDeviceProperties2 props{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2, &driver};
    vkGetPhysicalDeviceProperties2(pd, &props);
    seen +=
        std::string(seen.empty() ? "" : ", ") + std::to_string(index) + ": " + props.properties.deviceName;
    if (options.device_index >= 0 && size_t(options.device_index) != index) continue;
    if (props.properties.apiVersion < VK_API_VERSION_1_3) {
      if (options.device_index >= 0)
        return Error{ErrorCode::unsupported, std::string("device ") + std::to_string(index) + " (" +
                                                 props.properties.deviceName +
                                                 ") does not support Vulkan 1.3"};
      continue;
    }
    if (options.require_lavapipe && driver.driverID != VK_DRIVER_ID_MESA_LLVMPIPE) continue;
    physical_device = pd;
    device_name = props.properties.deviceName;
    driver_name = std::string(driver.driverName) + " " + driver.driverInfo;
    break;
  }
  if (!physical_device)
    return Error{
        ErrorCode::unsupported,
        std::string(options.require_lavapipe ? "no lavapipe device (apt-get install mesa-vulkan-drivers)"
                                             : "no Vulkan 1.3 device") +
            "; devices seen: " + (seen.empty() ? "none" : seen)};

  vkGetPhysicalDeviceQueueFamilyProperties(physical_device, &count, nullptr);
  std::vector<VkQueueFamilyProperties> families(count);
  vkGetPhysicalDeviceQueueFamilyProperties(physical_device, &count, families.data());
  for (uint32_t i = 0; i < count; ++i) {
    if ((families[i].queueFlags & (VK_QUEUE_GRAPHICS_BIT | VK_QUEUE_COMPUTE_BIT)) ==
        (VK_QUEUE_GRAPHICS_BIT | VK_QUEUE_COMPUTE_BIT)) {
      queue_family = i;
      return {};
    }
  }
  return Error{ErrorCode::unsupported, "no queue family with graphics and compute"};
}

// The device extensions that allow SPIR-V capabilities (vk.xml's table), those this device has and
// whose required extensions it has too, with their feature structures chained for vkGetPhysicalDevice-
// Features2 to fill; returns the chain's head. Their names go to enabled_extensions.
void* VulkanContext::chain_capability_extensions() {
  using namespace detail::capability_table;
  uint32_t count = 0;
  vkEnumerateDeviceExtensionProperties(physical_device, nullptr, &count, nullptr);
  std::vector<VkExtensionProperties> available(count);
  vkEnumerateDeviceExtensionProperties(physical_device, nullptr, &count, available.data());
  std::set<std::string_view> chosen;  // views of the table's literals, so .data() is a C string
  for (const ExtensionStruct& e : kCapabilityExtensions)
    for (const VkExtensionProperties& a : available)
      if (std::strcmp(a.extensionName, e.extension) == 0) chosen.insert(e.extension);
  for (bool dropped = true; dropped;) {  // without what it requires, an extension cannot be enabled
    dropped = false;
    for (const ExtensionDependency& d : kCapabilityExtensionDependencies)
      if (chosen.count(d.extension) && !chosen.count(d.needs)) dropped = chosen.erase(d.extension) > 0;
  }
  for (std::string_view name : chosen) capability_extension_names_.push_back(name.data());
  void* head = nullptr;
  for (const ExtensionStruct& e : kCapabilityExtensions) {
    if (!chosen.count(e.extension) || e.size == 0) continue;
    auto& bytes = capability_extension_features_.emplace_back(e.size, static_cast<unsigned char>(0));
    auto* s = reinterpret_cast<VkBaseOutStructure*>(bytes.data());
    s->sType = e.s_type;
    s->pNext = static_cast<VkBaseOutStructure*>(head);
    head = s;
  }
  return head;
}

Result<void> VulkanContext::create_device(const VulkanContextOptions& options) {
  // Members, not locals: device_context() hands the chain to the Dearchiver.
  VkPhysicalDeviceVulkan13Features& features13 = enabled_features13;
  VkPhysicalDeviceVulkan12Features& features12 = enabled_features12;
  VkPhysicalDeviceVulkan11Features& features11 = enabled_features11;
  VkPhysicalDeviceFeatures2& features = enabled_features2;
  features12.pNext = &features13;
  features11.pNext = &features12;
  features.pNext = &features13;
  if (options.enable_supported_features) {
    // Every core feature of Vulkan 1.0 to 1.3 the device has (multiview, buffer device addresses,
    // 8- and 16-bit storage, ...): what an archive's pipelines need, a verifying device must have on.
    features.pNext = &features11;
    features13.pNext = chain_capability_extensions();
    vkGetPhysicalDeviceFeatures2(physical_device, &features);
    // Robust access changes behaviour and costs speed; nothing archived needs it.
    features.features.robustBufferAccess = VK_FALSE;
    features13.robustImageAccess = VK_FALSE;
  }
  features13.dynamicRendering = VK_TRUE;
  enabled_features = features.features;
  const float priority = 1.0f;
  VkDeviceQueueCreateInfo queue_info{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
  queue_info.queueFamilyIndex = queue_family;
  queue_info.queueCount = 1;
  queue_info.pQueuePriorities = &priority;
  std::vector<const char*>& device_extensions = enabled_extensions;
  if (!options.instance_extensions.empty()) device_extensions.push_back(VK_KHR_SWAPCHAIN_EXTENSION_NAME);
  for (const char* name : capability_extension_names_) device_extensions.push_back(name);
  VkDeviceCreateInfo device_info{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
  device_info.pNext = &features;
  device_info.queueCreateInfoCount = 1;
  device_info.pQueueCreateInfos = &queue_info;
  device_info.enabledExtensionCount = static_cast<uint32_t>(device_extensions.size());
  device_info.ppEnabledExtensionNames = device_extensions.data();
  device_allocator = options.device_allocator;
  if (VkResult r = vkCreateDevice(physical_device, &device_info, device_allocator, &device); r != VK_SUCCESS)
    return vk_error("vkCreateDevice", r);
  vkGetDeviceQueue(device, queue_family, 0, &queue);
  VkCommandPoolCreateInfo pool_info{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
  pool_info.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
  pool_info.queueFamilyIndex = queue_family;
  if (VkResult r = vkCreateCommandPool(device, &pool_info, nullptr, &command_pool); r != VK_SUCCESS)
    return vk_error("vkCreateCommandPool", r);
  return {};
}

DeviceContext VulkanContext::device_context() const {
  DeviceContext context{physical_device, device};
  context.api_version = VK_API_VERSION_1_3;  // what create_instance asks for
  context.enabled_features = &enabled_features;
  context.enabled_feature_chain = &enabled_features2;
  context.enabled_extensions = enabled_extensions.data();
  context.enabled_extension_count = static_cast<uint32_t>(enabled_extensions.size());
  context.instance = instance;
  context.get_instance_proc_addr = vkGetInstanceProcAddr;
  return context;
}

void VulkanContext::destroy_device() {
  if (!device) return;
  vkDeviceWaitIdle(device);
  if (command_pool) vkDestroyCommandPool(device, command_pool, nullptr);
  vkDestroyDevice(device, device_allocator);
  device = VK_NULL_HANDLE;
  command_pool = VK_NULL_HANDLE;
}

VulkanContext::~VulkanContext() {
  destroy_device();
  if (messenger_) {
    auto destroy = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(instance, "vkDestroyDebugUtilsMessengerEXT"));
    destroy(instance, messenger_, nullptr);
  }
  if (instance) vkDestroyInstance(instance, nullptr);
}

std::vector<std::string> VulkanContext::validation_messages() const {
  std::lock_guard lock(mutex_);
  return messages_;
}

Result<void> VulkanContext::submit_and_wait(const std::function<void(VkCommandBuffer)>& record) {
  VkCommandBufferAllocateInfo alloc{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  alloc.commandPool = command_pool;
  alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  alloc.commandBufferCount = 1;
  VkCommandBuffer cmd = VK_NULL_HANDLE;
  if (VkResult r = vkAllocateCommandBuffers(device, &alloc, &cmd); r != VK_SUCCESS)
    return vk_error("vkAllocateCommandBuffers", r);
  VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  vkBeginCommandBuffer(cmd, &begin);
  record(cmd);
  vkEndCommandBuffer(cmd);
  VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
  submit.commandBufferCount = 1;
  submit.pCommandBuffers = &cmd;
  VkResult r = vkQueueSubmit(queue, 1, &submit, VK_NULL_HANDLE);
  if (r == VK_SUCCESS) r = vkQueueWaitIdle(queue);
  vkFreeCommandBuffers(device, command_pool, 1, &cmd);
  if (r != VK_SUCCESS) return vk_error("vkQueueSubmit", r);
  return {};
}

uint32_t VulkanContext::find_memory_type(uint32_t type_bits, VkMemoryPropertyFlags required) const {
  VkPhysicalDeviceMemoryProperties props;
  vkGetPhysicalDeviceMemoryProperties(physical_device, &props);
  for (uint32_t i = 0; i < props.memoryTypeCount; ++i)
    if ((type_bits & (1u << i)) && (props.memoryTypes[i].propertyFlags & required) == required) return i;
  return UINT32_MAX;
}

HostBuffer::~HostBuffer() {
  if (mapped) vkUnmapMemory(device, memory);
  if (buffer) vkDestroyBuffer(device, buffer, nullptr);
  if (memory) vkFreeMemory(device, memory, nullptr);
}

Result<std::unique_ptr<HostBuffer>> create_host_buffer(VulkanContext& vk, VkDeviceSize size,
                                                       VkBufferUsageFlags usage) {
  auto out = std::make_unique<HostBuffer>();
  out->device = vk.device;
  out->size = size;
  VkBufferCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
  info.size = size;
  info.usage = usage;
  if (VkResult r = vkCreateBuffer(vk.device, &info, nullptr, &out->buffer); r != VK_SUCCESS)
    return vk_error("vkCreateBuffer", r);
  VkMemoryRequirements req;
  vkGetBufferMemoryRequirements(vk.device, out->buffer, &req);
  VkMemoryAllocateInfo alloc{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
  alloc.allocationSize = req.size;
  alloc.memoryTypeIndex = vk.find_memory_type(
      req.memoryTypeBits, VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT);
  if (alloc.memoryTypeIndex == UINT32_MAX)
    return Error{ErrorCode::unsupported, "no host-visible coherent memory"};
  if (VkResult r = vkAllocateMemory(vk.device, &alloc, nullptr, &out->memory); r != VK_SUCCESS)
    return vk_error("vkAllocateMemory", r);
  vkBindBufferMemory(vk.device, out->buffer, out->memory, 0);
  if (VkResult r = vkMapMemory(vk.device, out->memory, 0, size, 0, &out->mapped); r != VK_SUCCESS)
    return vk_error("vkMapMemory", r);
  return out;
}

DeviceImage::~DeviceImage() {
  if (view) vkDestroyImageView(device, view, nullptr);
  if (image) vkDestroyImage(device, image, nullptr);
  if (memory) vkFreeMemory(device, memory, nullptr);
}

Result<std::unique_ptr<DeviceImage>> create_device_image(VulkanContext& vk, VkFormat format, uint32_t width,
                                                         uint32_t height, VkImageUsageFlags usage) {
  auto out = std::make_unique<DeviceImage>();
  out->device = vk.device;
  VkImageCreateInfo info{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
  info.imageType = VK_IMAGE_TYPE_2D;
  info.format = format;
  info.extent = {width, height, 1};
  info.mipLevels = info.arrayLayers = 1;
  info.samples = VK_SAMPLE_COUNT_1_BIT;
  info.tiling = VK_IMAGE_TILING_OPTIMAL;
  info.usage = usage;
  if (VkResult r = vkCreateImage(vk.device, &info, nullptr, &out->image); r != VK_SUCCESS)
    return vk_error("vkCreateImage", r);
  VkMemoryRequirements req;
  vkGetImageMemoryRequirements(vk.device, out->image, &req);
  VkMemoryAllocateInfo alloc{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
  alloc.allocationSize = req.size;
  alloc.memoryTypeIndex = vk.find_memory_type(req.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
  if (VkResult r = vkAllocateMemory(vk.device, &alloc, nullptr, &out->memory); r != VK_SUCCESS)
    return vk_error("vkAllocateMemory", r);
  vkBindImageMemory(vk.device, out->image, out->memory, 0);
  VkImageViewCreateInfo view{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
  view.image = out->image;
  view.viewType = VK_IMAGE_VIEW_TYPE_2D;
  view.format = format;
  view.subresourceRange = {format_aspects(format), 0, 1, 0, 1};
  if (VkResult r = vkCreateImageView(vk.device, &view, nullptr, &out->view); r != VK_SUCCESS)
    return vk_error("vkCreateImageView", r);
  return out;
}

VkImageAspectFlags format_aspects(VkFormat format) {
  switch (format) {
    case VK_FORMAT_D16_UNORM:
    case VK_FORMAT_X8_D24_UNORM_PACK32:
    case VK_FORMAT_D32_SFLOAT:
      return VK_IMAGE_ASPECT_DEPTH_BIT;
    case VK_FORMAT_S8_UINT:
      return VK_IMAGE_ASPECT_STENCIL_BIT;
    case VK_FORMAT_D16_UNORM_S8_UINT:
    case VK_FORMAT_D24_UNORM_S8_UINT:
    case VK_FORMAT_D32_SFLOAT_S8_UINT:
      return VK_IMAGE_ASPECT_DEPTH_BIT | VK_IMAGE_ASPECT_STENCIL_BIT;
    default:
      return VK_IMAGE_ASPECT_COLOR_BIT;
  }
}

void image_barrier(VkCommandBuffer cmd, VkImage image, VkImageLayout from, VkImageLayout to,
                   VkAccessFlags src_access, VkAccessFlags dst_access, VkPipelineStageFlags src_stage,
                   VkPipelineStageFlags dst_stage, VkImageAspectFlags aspects) {
  VkImageMemoryBarrier b{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER};
  b.srcAccessMask = src_access;
  b.dstAccessMask = dst_access;
  b.oldLayout = from;
  b.newLayout = to;
  b.srcQueueFamilyIndex = b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  b.image = image;
  b.subresourceRange = {aspects, 0, 1, 0, 1};
  vkCmdPipelineBarrier(cmd, src_stage, dst_stage, 0, 0, nullptr, 0, nullptr, 1, &b);
}

StorageBufferSet::~StorageBufferSet() {
  if (pool) vkDestroyDescriptorPool(device, pool, nullptr);  // frees the set too
}

Result<std::unique_ptr<StorageBufferSet>> bind_storage_buffer(VulkanContext& vk, VkDescriptorSetLayout layout,
                                                              uint32_t binding, VkBuffer buffer) {
  auto out = std::make_unique<StorageBufferSet>();
  out->device = vk.device;
  VkDescriptorPoolSize pool_size{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1};
  VkDescriptorPoolCreateInfo pool_info{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
  pool_info.maxSets = 1;
  pool_info.poolSizeCount = 1;
  pool_info.pPoolSizes = &pool_size;
  if (VkResult r = vkCreateDescriptorPool(vk.device, &pool_info, nullptr, &out->pool); r != VK_SUCCESS)
    return vk_error("vkCreateDescriptorPool", r);
  VkDescriptorSetAllocateInfo alloc{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
  alloc.descriptorPool = out->pool;
  alloc.descriptorSetCount = 1;
  alloc.pSetLayouts = &layout;
  if (VkResult r = vkAllocateDescriptorSets(vk.device, &alloc, &out->set); r != VK_SUCCESS)
    return vk_error("vkAllocateDescriptorSets", r);
  VkDescriptorBufferInfo buffer_info{buffer, 0, VK_WHOLE_SIZE};
  VkWriteDescriptorSet write{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
  write.dstSet = out->set;
  write.dstBinding = binding;
  write.descriptorCount = 1;
  write.descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
  write.pBufferInfo = &buffer_info;
  vkUpdateDescriptorSets(vk.device, 1, &write, 0, nullptr);
  return out;
}

}  // namespace statepack::bootstrap
