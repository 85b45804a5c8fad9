// A shader's SPIR-V capabilities against the features the application created its device with
// (DeviceContext::enabled_feature_chain): one that nothing enables is an `unsupported` error naming the
// features that would allow it, before vkCreateShaderModule (the fixture fails on any validation
// message); with the features on, the same pipelines unpack.
#include <cstddef>

#include "common/vulkan_test_fixture.hpp"

namespace statepack::testing {
namespace {

class CapabilityFeaturesTest : public VulkanTest {
 protected:
  // The device's own chain, copied, so that a test can say a feature is off.
  struct Chain {
    VkPhysicalDeviceFeatures2 f2;
    VkPhysicalDeviceVulkan11Features f11;
    VkPhysicalDeviceVulkan12Features f12;
    VkPhysicalDeviceVulkan13Features f13;
  };
  static void link(Chain& c) {
    c.f2.pNext = &c.f11;
    c.f11.pNext = &c.f12;
    c.f12.pNext = &c.f13;
    c.f13.pNext = nullptr;
  }
  Chain device_chain() const {
    Chain c{vk_->enabled_features2, vk_->enabled_features11, vk_->enabled_features12,
            vk_->enabled_features13};
    link(c);
    return c;
  }
  Result<Dearchiver> dearchiver_with(const DeviceContext& context) const {
    auto archive = Archive::from_file(STATEPACK_CAPABILITIES_ARCHIVE);
    if (!archive) return archive.error();
    auto dearchiver = Dearchiver::create(context);
    if (!dearchiver) return dearchiver.error();
    if (auto added = dearchiver->add_archive(std::move(*archive)); !added) return added.error();
    return dearchiver;
  }
};

TEST_F(CapabilityFeaturesTest, AFeatureLeftOutOfTheChainIsNamedBeforeAnyVulkanCall) {
  ASSERT_TRUE(vk_->enabled_features12.shaderInt8 && vk_->enabled_features2.features.shaderFloat64)
      << "lavapipe has both; the test needs them on to say they are off";
  Chain chain = device_chain();
  chain.f12.shaderInt8 = VK_FALSE;
  chain.f2.features.shaderFloat64 = VK_FALSE;
  DeviceContext context = vk_->device_context();
  context.enabled_feature_chain = &chain.f2;
  context.enabled_features = nullptr;  // the chain's VkPhysicalDeviceFeatures2 says it
  auto dearchiver = dearchiver_with(context);
  ASSERT_TRUE(dearchiver) << dearchiver.error().message;
  auto int8 = dearchiver->unpack_compute("Int8 PSO");
  ASSERT_FALSE(int8);
  EXPECT_EQ(int8.error().code, ErrorCode::unsupported);
  EXPECT_EQ(
      int8.error().message,
      "shader 'Int8 CS' declares the SPIR-V capability Int8, which needs one of: "
      "VkPhysicalDeviceVulkan12Features::shaderInt8, VkPhysicalDeviceShaderFloat16Int8Features::shaderInt8; "
      "none is enabled on this device (DeviceContext::enabled_feature_chain and enabled_extensions say "
      "what the device was created with)");
  auto float64 = dearchiver->unpack_compute("Float64 PSO");
  ASSERT_FALSE(float64);
  EXPECT_EQ(float64.error().code, ErrorCode::unsupported);
  EXPECT_NE(float64.error().message.find("declares the SPIR-V capability Float64, which needs one of: "
                                         "VkPhysicalDeviceFeatures::shaderFloat64;"),
            std::string::npos)
      << float64.error().message;
}

TEST_F(CapabilityFeaturesTest, AStructureMissingFromTheChainCountsAsOff) {
  Chain chain = device_chain();
  chain.f11.pNext = nullptr;  // no Vulkan12Features: shaderInt8 off, even though the device has it
  DeviceContext context = vk_->device_context();
  context.enabled_feature_chain = &chain.f2;
  auto dearchiver = dearchiver_with(context);
  ASSERT_TRUE(dearchiver) << dearchiver.error().message;
  auto int8 = dearchiver->unpack_compute("Int8 PSO");
  ASSERT_FALSE(int8);
  EXPECT_EQ(int8.error().code, ErrorCode::unsupported);
  EXPECT_TRUE(dearchiver->unpack_compute("Float64 PSO"));  // VkPhysicalDeviceFeatures2 is still there
}

TEST_F(CapabilityFeaturesTest, TheFeaturesTheDeviceWasCreatedWithLetThemUnpack) {
  auto dearchiver = dearchiver_with(vk_->device_context());
  ASSERT_TRUE(dearchiver) << dearchiver.error().message;
  EXPECT_TRUE(dearchiver->unpack_compute("Int8 PSO"));
  EXPECT_TRUE(dearchiver->unpack_compute("Float64 PSO"));
}

// The fixture's device has the extensions that allow capabilities (the bootstrap enables those it
// has, as verify's device does); an application that did not enable one is told which.
TEST_F(CapabilityFeaturesTest, CapabilitiesThatNeedAnExtensionNameIt) {
  auto dearchiver = dearchiver_with(vk_->device_context());
  ASSERT_TRUE(dearchiver) << dearchiver.error().message;
  auto clock = dearchiver->unpack_compute("Clock PSO");
  EXPECT_TRUE(clock) << clock.error().message;
  auto atomic = dearchiver->unpack_compute("Atomic Float PSO");
  EXPECT_TRUE(atomic) << atomic.error().message;

  const char* none[1] = {nullptr};
  DeviceContext without = vk_->device_context();
  without.enabled_extensions = none;
  without.enabled_extension_count = 0;
  Chain chain = device_chain();  // the atomic-float structure is not in this copy: off
  without.enabled_feature_chain = &chain.f2;
  auto bare = dearchiver_with(without);
  ASSERT_TRUE(bare) << bare.error().message;
  auto unclocked = bare->unpack_compute("Clock PSO");
  ASSERT_FALSE(unclocked);
  EXPECT_EQ(unclocked.error().code, ErrorCode::unsupported);
  EXPECT_EQ(
      unclocked.error().message,
      "shader 'Clock CS' declares the SPIR-V capability ShaderClockKHR, which needs one of: the extension "
      "VK_KHR_shader_clock; none is enabled on this device (DeviceContext::enabled_feature_chain and "
      "enabled_extensions say what the device was created with)");
  auto no_atomic = bare->unpack_compute("Atomic Float PSO");
  ASSERT_FALSE(no_atomic);
  EXPECT_NE(no_atomic.error().message.find(
                "AtomicFloat32AddEXT, which needs one of: "
                "VkPhysicalDeviceShaderAtomicFloatFeaturesEXT::shaderBufferFloat32AtomicAdd"),
            std::string::npos)
      << no_atomic.error().message;
}

// Blend states compare by their fields: two render targets blended alike need no independentBlend,
// whatever the bytes between a BlendAttachmentState's fields hold (they were once compared as raw memory,
// so a callback's copy could be refused on a device without the feature).
TEST_F(CapabilityFeaturesTest, RenderTargetsBlendedAlikeNeedNoIndependentBlend) {
  std::string path;
  for (const auto& p : corpus_archives())
    if (p.find("imports_and_defaults") != std::string::npos) path = p;
  ASSERT_FALSE(path.empty());
  Chain chain = device_chain();
  chain.f2.features.independentBlend = VK_FALSE;
  DeviceContext context = vk_->device_context();
  context.enabled_feature_chain = &chain.f2;
  context.enabled_features = nullptr;
  auto archive = Archive::from_file(path);
  ASSERT_TRUE(archive) << archive.error().message;
  auto dearchiver = Dearchiver::create(context);
  ASSERT_TRUE(dearchiver) << dearchiver.error().message;
  ASSERT_TRUE(dearchiver->add_archive(std::move(*archive)));
  static_assert(offsetof(BlendAttachmentState, src_color) > sizeof(bool), "padding after `enable`");
  auto alike = dearchiver->unpack_graphics("Two Targets PSO", [](PatchableState& s) {
    s.blend[1] = s.blend[0];
    auto* bytes = reinterpret_cast<unsigned char*>(&s.blend[1]);
    for (size_t i = sizeof(bool); i < offsetof(BlendAttachmentState, src_color); ++i) bytes[i] = 0xA5;
  });
  EXPECT_TRUE(alike) << alike.error().message;
  auto different = dearchiver->unpack_graphics(
      "Two Targets PSO", [](PatchableState& s) { s.blend[1].enable = !s.blend[0].enable; });
  ASSERT_FALSE(different);
  EXPECT_EQ(different.error().code, ErrorCode::unsupported);
  EXPECT_EQ(different.error().message,
            "pipeline 'Two Targets PSO' needs the device feature 'independentBlend', which is not enabled "
            "(DeviceContext::enabled_features says what the device was created with)");
}

// Null means what it means to vkCreateDevice: nothing enabled. A device that supports shaderInt8 (as
// lavapipe does) still refuses an Int8 shader unless the application enabled it, so the Dearchiver does
// too, before any Vulkan call, rather than let the validation layer find it.
TEST_F(CapabilityFeaturesTest, WithoutAChainNothingIsEnabled) {
  DeviceContext context{vk_->physical_device, vk_->device};
  auto dearchiver = dearchiver_with(context);
  ASSERT_TRUE(dearchiver) << dearchiver.error().message;
  auto int8 = dearchiver->unpack_compute("Int8 PSO");
  ASSERT_FALSE(int8);
  EXPECT_EQ(int8.error().code, ErrorCode::unsupported);
  EXPECT_NE(
      int8.error().message.find("Int8, which needs one of: VkPhysicalDeviceVulkan12Features::shaderInt8"),
      std::string::npos)
      << int8.error().message;
  auto clock = dearchiver->unpack_compute("Clock PSO");
  ASSERT_FALSE(clock);
  EXPECT_NE(clock.error().message.find("the extension VK_KHR_shader_clock"), std::string::npos)
      << clock.error().message;
  EXPECT_TRUE(vk_->validation_messages().empty()) << vk_->validation_messages().front();
}

}  // namespace
}  // namespace statepack::testing
