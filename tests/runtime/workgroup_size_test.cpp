// A compute shader's work-group size is checked against the device before Vulkan sees it
// (VUID-RuntimeSpirv-x-06429 to -06432): the literal size of the module, and the size a specialization
// constant gives it, as the pipeline or the modify callback sets it. The fixture fails on any
// validation message, so none of these reaches the driver.
#include <cstring>

#include "common/vulkan_test_fixture.hpp"

namespace statepack::testing {
namespace {

class WorkgroupSizeTest : public VulkanTest {
 protected:
  Dearchiver load() {
    auto dearchiver = Dearchiver::create(vk_->device_context());
    EXPECT_TRUE(dearchiver);
    auto archive = Archive::from_file(STATEPACK_WORKGROUP_ARCHIVE);
    EXPECT_TRUE(archive) << archive.error().message;
    EXPECT_TRUE(dearchiver->add_archive(std::move(*archive)));
    return std::move(*dearchiver);
  }
  // The size lavapipe allows in x (the tests below depend on it being below 2048).
  uint32_t max_x() const {
    VkPhysicalDeviceProperties properties;
    vkGetPhysicalDeviceProperties(vk_->physical_device, &properties);
    return properties.limits.maxComputeWorkGroupSize[0];
  }
};

TEST_F(WorkgroupSizeTest, TooManyInvocationsAreTheDevicesLimitNamed) {
  Dearchiver dearchiver = load();
  VkPhysicalDeviceProperties properties;
  vkGetPhysicalDeviceProperties(vk_->physical_device, &properties);
  ASSERT_LT(properties.limits.maxComputeWorkGroupInvocations, 2048u);
  auto wide = dearchiver.unpack_compute("Wide");
  ASSERT_FALSE(wide);
  EXPECT_EQ(wide.error().code, ErrorCode::unsupported);
  EXPECT_EQ(wide.error().message,
            "pipeline 'Wide': a work group of 32 x 32 x 2 is 2048 invocations, beyond the device's "
            "maxComputeWorkGroupInvocations of " +
                std::to_string(properties.limits.maxComputeWorkGroupInvocations));
}

TEST_F(WorkgroupSizeTest, TheSizeASpecializationGivesIsChecked) {
  Dearchiver dearchiver = load();
  ASSERT_LT(max_x(), 2048u);
  // The archive's own value (64) is fine, and the pipeline runs with it.
  auto sized = dearchiver.unpack_compute("Sized");
  ASSERT_TRUE(sized) << sized.error().message;
  // The modify callback widens it beyond the device: refused before any Vulkan call, naming the limit.
  auto wider =
      dearchiver.unpack_compute("Sized", [](PatchableState& s) { s.set_constant("kGroupX", 2048u); });
  ASSERT_FALSE(wider);
  EXPECT_EQ(wider.error().code, ErrorCode::unsupported);
  EXPECT_EQ(wider.error().message.rfind("pipeline 'Sized': the work-group size 2048 x 1 x 1 is beyond the "
                                        "device's maxComputeWorkGroupSize of (" +
                                            std::to_string(max_x()) + ", ",
                                        0),
            0u)
      << wider.error().message;
  // Zero is no size at all: the caller's mistake, not the device's.
  auto zero = dearchiver.unpack_compute("Sized", [](PatchableState& s) { s.set_constant("kGroupX", 0u); });
  ASSERT_FALSE(zero);
  EXPECT_EQ(zero.error().code, ErrorCode::invalid_argument);
  EXPECT_EQ(zero.error().message,
            "pipeline 'Sized': the work-group size is 0 x 1 x 1; each dimension must be at least 1");
  // At the device's own limit it is created (and the layer, which checks the same rule, says nothing).
  const uint32_t at_limit = std::min(max_x(), 1024u);
  auto widest =
      dearchiver.unpack_compute("Sized", [&](PatchableState& s) { s.set_constant("kGroupX", at_limit); });
  EXPECT_TRUE(widest) << widest.error().message;
}

}  // namespace
}  // namespace statepack::testing
