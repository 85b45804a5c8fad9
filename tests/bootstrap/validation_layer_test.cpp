// Proves the test harness can fail: the validation layer is really loaded on lavapipe and the
// messenger records what it reports. Without this, a silent harness would pass every Vulkan test.
#include <gtest/gtest.h>

#include <bit>

#include "statepack/bootstrap/vulkan_context.hpp"

namespace {

TEST(ValidationLayer, InvalidUsageIsRecorded) {
  statepack::bootstrap::VulkanContextOptions options;
  options.validation = true;
  options.require_lavapipe = true;
  auto vk = statepack::bootstrap::VulkanContext::create(options);
  ASSERT_TRUE(vk) << vk.error().message;
  EXPECT_NE((*vk)->driver_name.find("llvmpipe"), std::string::npos) << (*vk)->driver_name;
  ASSERT_TRUE((*vk)->validation_messages().empty());

  VkBufferCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
  info.size = 0;  // VUID-VkBufferCreateInfo-size-00912: size must be greater than 0
  info.usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
  VkBuffer buffer = VK_NULL_HANDLE;
  vkCreateBuffer((*vk)->device, &info, nullptr, &buffer);
  if (buffer) vkDestroyBuffer((*vk)->device, buffer, nullptr);

  auto messages = (*vk)->validation_messages();
  ASSERT_FALSE(messages.empty()) << "the validation layer reported nothing for an invalid call";
  EXPECT_NE(messages.front().find("00912"), std::string::npos) << messages.front();
}

}  // namespace

namespace {

// The fixture's leak check: destroying a device with live children is reported by the layer.
TEST(ValidationLayer, ObjectsLeftAliveAreReportedAtDeviceDestruction) {
  statepack::bootstrap::VulkanContextOptions options;
  options.require_lavapipe = true;
  auto vk = statepack::bootstrap::VulkanContext::create(options);
  ASSERT_TRUE(vk) << vk.error().message;
  VkBufferCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
  info.size = 64;
  info.usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
  VkBuffer buffer = VK_NULL_HANDLE;
  ASSERT_EQ(vkCreateBuffer((*vk)->device, &info, nullptr, &buffer), VK_SUCCESS);
  (*vk)->destroy_device();  // deliberately with the buffer alive
  auto messages = (*vk)->validation_messages();
  ASSERT_FALSE(messages.empty());
  EXPECT_NE(messages.front().find("not been destroyed"), std::string::npos) << messages.front();
}

}  // namespace

namespace {

// The messenger tells the layer's performance advice from its validity reports: `statepack verify`
// reports an object with only performance warnings as ok (every test still fails on any message).
TEST(ValidationLayer, PerformanceWarningsAreMarkedAsSuch) {
  statepack::bootstrap::VulkanContextOptions options;
  options.require_lavapipe = true;
  auto vk = statepack::bootstrap::VulkanContext::create(options);
  ASSERT_TRUE(vk) << vk.error().message;
  auto submit = reinterpret_cast<PFN_vkSubmitDebugUtilsMessageEXT>(
      vkGetInstanceProcAddr((*vk)->instance, "vkSubmitDebugUtilsMessageEXT"));
  ASSERT_NE(submit, nullptr);
  VkDebugUtilsMessengerCallbackDataEXT data{VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CALLBACK_DATA_EXT};
  data.pMessage = "an output no stage reads";
  submit((*vk)->instance, VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT,
         VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT, &data);
  submit((*vk)->instance, VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT,
         VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT, &data);
  submit((*vk)->instance, VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT,
         VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT, &data);
  EXPECT_EQ(
      (*vk)->validation_messages(),
      (std::vector<std::string>{
          std::string(statepack::bootstrap::kPerformanceWarning) + "an output no stage reads",
          "validation warning: an output no stage reads", "validation error: an output no stage reads"}));
}

}  // namespace

namespace {

// Synchronization validation is on wherever the layer is: two transfer writes to one buffer in one
// command buffer with no barrier between them are a write-after-write hazard the layer reports. Without
// it a missing barrier in the renderer or the unpack tests would pass.
TEST(ValidationLayer, MissingBarriersAreReported) {
  statepack::bootstrap::VulkanContextOptions options;
  options.require_lavapipe = true;
  auto vk = statepack::bootstrap::VulkanContext::create(options);
  ASSERT_TRUE(vk) << vk.error().message;
  VkDevice device = (*vk)->device;
  VkBufferCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
  info.size = 256;
  info.usage = VK_BUFFER_USAGE_TRANSFER_DST_BIT;
  VkBuffer buffer = VK_NULL_HANDLE;
  ASSERT_EQ(vkCreateBuffer(device, &info, nullptr, &buffer), VK_SUCCESS);
  VkMemoryRequirements needs{};
  vkGetBufferMemoryRequirements(device, buffer, &needs);
  VkMemoryAllocateInfo allocate{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
  allocate.allocationSize = needs.size;
  allocate.memoryTypeIndex = uint32_t(std::countr_zero(needs.memoryTypeBits));
  VkDeviceMemory memory = VK_NULL_HANDLE;
  ASSERT_EQ(vkAllocateMemory(device, &allocate, nullptr, &memory), VK_SUCCESS);
  ASSERT_EQ(vkBindBufferMemory(device, buffer, memory, 0), VK_SUCCESS);

  VkCommandBufferAllocateInfo cb_info{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  cb_info.commandPool = (*vk)->command_pool;
  cb_info.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  cb_info.commandBufferCount = 1;
  VkCommandBuffer cmd = VK_NULL_HANDLE;
  ASSERT_EQ(vkAllocateCommandBuffers(device, &cb_info, &cmd), VK_SUCCESS);
  VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  vkBeginCommandBuffer(cmd, &begin);
  vkCmdFillBuffer(cmd, buffer, 0, VK_WHOLE_SIZE, 1);
  vkCmdFillBuffer(cmd, buffer, 0, VK_WHOLE_SIZE, 2);  // no barrier: WRITE_AFTER_WRITE
  vkEndCommandBuffer(cmd);
  auto messages = (*vk)->validation_messages();
  vkFreeCommandBuffers(device, (*vk)->command_pool, 1, &cmd);
  vkDestroyBuffer(device, buffer, nullptr);
  vkFreeMemory(device, memory, nullptr);
  ASSERT_FALSE(messages.empty()) << "synchronization validation reported nothing for a missing barrier";
  EXPECT_NE(messages.front().find("SYNC-HAZARD-WRITE-AFTER-WRITE"), std::string::npos) << messages.front();
}

}  // namespace
