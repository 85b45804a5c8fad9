// Dynamic state as Diligent's Vulkan backend has it: one archived pipeline draws three times in one
// rendering pass with different blend constants, stencil references and (an extended dynamic state
// the notation asked for) stencil ops; the pixels show each draw's values.
#include <array>

#include "common/vulkan_test_fixture.hpp"

namespace statepack::testing {
namespace {

class DynamicStateTest : public VulkanTest {};

TEST_F(DynamicStateTest, OnePipelineServesDrawsWithDifferentBlendConstantsAndStencilReferences) {
  auto dearchiver = Dearchiver::create({vk_->physical_device, vk_->device});
  ASSERT_TRUE(dearchiver);
  auto archive = Archive::from_file(STATEPACK_DYNAMIC_STATE_ARCHIVE);
  ASSERT_TRUE(archive) << archive.error().message;
  ASSERT_TRUE(dearchiver->add_archive(std::move(*archive)));
  std::vector<VkDynamicState> seen;
  auto pso =
      dearchiver->unpack_graphics("Constant Color PSO", [&](PatchableState& s) { seen = s.dynamic_states; });
  ASSERT_TRUE(pso) << pso.error().message;
  EXPECT_EQ(seen, (std::vector<VkDynamicState>{
                      VK_DYNAMIC_STATE_VIEWPORT, VK_DYNAMIC_STATE_SCISSOR, VK_DYNAMIC_STATE_BLEND_CONSTANTS,
                      VK_DYNAMIC_STATE_STENCIL_REFERENCE, VK_DYNAMIC_STATE_STENCIL_OP}));

  constexpr uint32_t kSize = 8;
  auto color =
      bootstrap::create_device_image(*vk_, VK_FORMAT_R8G8B8A8_UNORM, kSize, kSize,
                                     VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT);
  auto depth = bootstrap::create_device_image(*vk_, VK_FORMAT_D24_UNORM_S8_UINT, kSize, kSize,
                                              VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT);
  ASSERT_TRUE(color && depth);
  auto readback = bootstrap::create_host_buffer(*vk_, kSize * kSize * 4, VK_BUFFER_USAGE_TRANSFER_DST_BIT);
  ASSERT_TRUE(readback);
  auto done = vk_->submit_and_wait([&](VkCommandBuffer cmd) {
    bootstrap::image_barrier(cmd, (*color)->image, VK_IMAGE_LAYOUT_UNDEFINED,
                             VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, 0,
                             VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT,
                             VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT);
    bootstrap::image_barrier(
        cmd, (*depth)->image, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL, 0,
        VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT | VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_READ_BIT,
        VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT,
        VK_PIPELINE_STAGE_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT,
        VK_IMAGE_ASPECT_DEPTH_BIT | VK_IMAGE_ASPECT_STENCIL_BIT);
    VkRenderingAttachmentInfo color_attachment{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
    color_attachment.imageView = (*color)->view;
    color_attachment.imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
    color_attachment.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
    color_attachment.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    VkRenderingAttachmentInfo stencil{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
    stencil.imageView = (*depth)->view;
    stencil.imageLayout = VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL;
    stencil.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
    stencil.storeOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
    VkRenderingInfo rendering{VK_STRUCTURE_TYPE_RENDERING_INFO};
    rendering.renderArea = {{0, 0}, {kSize, kSize}};
    rendering.layerCount = 1;
    rendering.colorAttachmentCount = 1;
    rendering.pColorAttachments = &color_attachment;
    rendering.pDepthAttachment = &stencil;
    rendering.pStencilAttachment = &stencil;
    vkCmdBeginRendering(cmd, &rendering);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, (*pso)->pipeline);
    VkViewport viewport{0, 0, float(kSize), float(kSize), 0, 1};
    vkCmdSetViewport(cmd, 0, 1, &viewport);
    struct Draw {
      VkRect2D scissor;
      std::array<float, 4> constants;
      uint32_t reference;
      VkCompareOp compare;
    };
    const VkRect2D left{{0, 0}, {kSize / 2, kSize}}, right{{int32_t(kSize / 2), 0}, {kSize / 2, kSize}},
        all{{0, 0}, {kSize, kSize}};
    const Draw draws[] = {
        {left, {1, 0, 0, 1}, 3, VK_COMPARE_OP_ALWAYS},   // red, stencil 3 on the left
        {right, {0, 0, 1, 1}, 9, VK_COMPARE_OP_ALWAYS},  // blue, stencil 9 on the right
        {all, {0, 1, 0, 1}, 9, VK_COMPARE_OP_EQUAL},     // green only where the stencil is 9
    };
    for (const Draw& d : draws) {
      vkCmdSetScissor(cmd, 0, 1, &d.scissor);
      vkCmdSetBlendConstants(cmd, d.constants.data());
      vkCmdSetStencilReference(cmd, VK_STENCIL_FACE_FRONT_AND_BACK, d.reference);
      vkCmdSetStencilOp(cmd, VK_STENCIL_FACE_FRONT_AND_BACK, VK_STENCIL_OP_KEEP, VK_STENCIL_OP_REPLACE,
                        VK_STENCIL_OP_KEEP, d.compare);
      vkCmdDraw(cmd, 3, 1, 0, 0);
    }
    vkCmdEndRendering(cmd);
    bootstrap::image_barrier(cmd, (*color)->image, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                             VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT,
                             VK_ACCESS_TRANSFER_READ_BIT, VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT,
                             VK_PIPELINE_STAGE_TRANSFER_BIT);
    VkBufferImageCopy copy{};
    copy.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    copy.imageExtent = {kSize, kSize, 1};
    vkCmdCopyImageToBuffer(cmd, (*color)->image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, (*readback)->buffer, 1,
                           &copy);
  });
  ASSERT_TRUE(done) << done.error().message;
  const auto* pixels = static_cast<const uint8_t*>((*readback)->mapped);
  for (uint32_t y = 0; y < kSize; ++y)
    for (uint32_t x = 0; x < kSize; ++x) {
      const uint8_t* p = pixels + (size_t(y) * kSize + x) * 4;
      const std::array<uint8_t, 4> want =
          x < kSize / 2 ? std::array<uint8_t, 4>{255, 0, 0, 255} : std::array<uint8_t, 4>{0, 255, 0, 255};
      for (int c = 0; c < 4; ++c)
        ASSERT_EQ(p[c], want[c]) << "pixel (" << x << ", " << y << ") channel " << c;
    }
}

TEST_F(DynamicStateTest, UnsupportedDynamicStatesAreErrorsNamingThem) {
  auto dearchiver = Dearchiver::create({vk_->physical_device, vk_->device});
  ASSERT_TRUE(dearchiver);
  auto archive = Archive::from_file(STATEPACK_DYNAMIC_STATE_ARCHIVE);
  ASSERT_TRUE(archive);
  ASSERT_TRUE(dearchiver->add_archive(std::move(*archive)));
  auto with_count = dearchiver->unpack_graphics("Constant Color PSO", [](PatchableState& s) {
    s.dynamic_states.push_back(VK_DYNAMIC_STATE_VIEWPORT_WITH_COUNT);
  });
  ASSERT_FALSE(with_count);
  EXPECT_EQ(with_count.error().message,
            "pipeline 'Constant Color PSO': dynamic state VK_DYNAMIC_STATE_VIEWPORT_WITH_COUNT is not "
            "supported by the dearchiver");
  auto no_scissor = dearchiver->unpack_graphics(
      "Constant Color PSO", [](PatchableState& s) { s.dynamic_states.erase(s.dynamic_states.begin() + 1); });
  ASSERT_FALSE(no_scissor);
  EXPECT_EQ(no_scissor.error().message,
            "pipeline 'Constant Color PSO': viewport and scissor must stay dynamic (the modify callback "
            "removed one)");
  // Adding one that the device has works (line width: every device).
  auto line_width = dearchiver->unpack_graphics("Constant Color PSO", [](PatchableState& s) {
    s.dynamic_states.push_back(VK_DYNAMIC_STATE_LINE_WIDTH);
  });
  EXPECT_TRUE(line_width) << line_width.error().message;
}

}  // namespace
}  // namespace statepack::testing
