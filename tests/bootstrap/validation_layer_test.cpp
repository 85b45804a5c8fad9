// Proves the test harness can fail: the validation layer is really loaded on lavapipe and the
// messenger records what it reports. Without this, a silent harness would pass every Vulkan test.
#include <gtest/gtest.h>

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
