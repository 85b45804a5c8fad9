// GoogleTest fixture for every Vulkan test: lavapipe only, validation layer on, and any validation
// warning or error fails the test that caused it.
#pragma once

#include <gtest/gtest.h>

#include <array>
#include <cstring>
#include <functional>
#include <memory>
#include <span>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "statepack/bootstrap/vulkan_context.hpp"
#include "statepack/dearchiver.hpp"

namespace statepack::testing {

// The archives built from tests/corpus/valid (their paths come from CMake, '|'-separated).
inline std::vector<std::string> corpus_archives() {
  std::vector<std::string> out;
  std::istringstream list(STATEPACK_CORPUS_ARCHIVES);
  for (std::string path; std::getline(list, path, '|');)
    if (!path.empty()) out.push_back(path);
  return out;
}

// The corpus archives whose pipelines unpack without a modify callback. A corpus file named run_time_*
// leaves state to the application's callback (render targets, as Diligent's Tutorial25 does), so
// unpacking it unpatched is an error by design (tested in CorpusUnpack).
inline std::vector<std::string> corpus_archives_without_run_time_state() {
  std::vector<std::string> out;
  for (auto& path : corpus_archives())
    if (path.find("/run_time_") == std::string::npos) out.push_back(std::move(path));
  return out;
}

class VulkanTest : public ::testing::Test {
 protected:
  void SetUp() override {
    bootstrap::VulkanContextOptions options;
    options.validation = true;
    options.require_lavapipe = true;
    // Every feature lavapipe has is enabled, and vk_->device_context() tells the Dearchiver so.
    options.enable_supported_features = true;
    auto created = bootstrap::VulkanContext::create(options);
    ASSERT_TRUE(created) << created.error().message;
    vk_ = std::move(created.value());
  }

  void TearDown() override {
    if (!vk_) return;
    vk_->destroy_device();  // the layer reports Vulkan objects the test (or the dearchiver) leaked
    for (const auto& message : vk_->validation_messages()) ADD_FAILURE() << message;
  }

  // A dearchiver with the test archive loaded (built by statepack_add_archive in tests/CMakeLists.txt).
  Dearchiver make_dearchiver() {
    auto dearchiver = Dearchiver::create(vk_->device_context());
    EXPECT_TRUE(dearchiver) << dearchiver.error().message;
    auto archive = Archive::from_file(STATEPACK_TEST_ARCHIVE);
    EXPECT_TRUE(archive) << archive.error().message;
    auto added = dearchiver->add_archive(std::move(archive.value()));
    EXPECT_TRUE(added);
    return std::move(dearchiver.value());
  }

  // One render target of a draw: its format and the bytes of one of its pixels.
  struct TargetFormat {
    VkFormat format;
    uint32_t bytes_per_pixel;
  };
  // The images a draw rendered into, left in SHADER_READ_ONLY_OPTIMAL for a pass that samples them,
  // and their bytes, read back.
  struct RenderedTargets {
    std::vector<std::unique_ptr<bootstrap::DeviceImage>> images;
    std::vector<std::vector<uint8_t>> pixels;
  };

  // Draws `pso` (a full-screen triangle, 3 vertices) into new width x height images, one per target;
  // `bind` records what the draw needs bound besides the pipeline.
  RenderedTargets render_targets(const UnpackedPipeline& pso, std::span<const TargetFormat> targets,
                                 uint32_t width, uint32_t height,
                                 const std::function<void(VkCommandBuffer)>& bind = {}) {
    RenderedTargets out;
    std::vector<std::unique_ptr<bootstrap::HostBuffer>> readbacks;
    for (const TargetFormat& t : targets) {
      auto image = bootstrap::create_device_image(
          *vk_, t.format, width, height,
          VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT);
      EXPECT_TRUE(image) << image.error().message;
      auto readback = bootstrap::create_host_buffer(*vk_, VkDeviceSize(width) * height * t.bytes_per_pixel,
                                                    VK_BUFFER_USAGE_TRANSFER_DST_BIT);
      EXPECT_TRUE(readback);
      if (!image || !readback) return {};
      out.images.push_back(std::move(*image));
      readbacks.push_back(std::move(*readback));
    }
    auto submitted = vk_->submit_and_wait([&](VkCommandBuffer cmd) {
      std::vector<VkRenderingAttachmentInfo> colors;
      for (const auto& image : out.images) {
        bootstrap::image_barrier(cmd, image->image, VK_IMAGE_LAYOUT_UNDEFINED,
                                 VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, 0,
                                 VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT,
                                 VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT);
        VkRenderingAttachmentInfo color{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
        color.imageView = image->view;
        color.imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
        color.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
        color.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
        colors.push_back(color);
      }
      VkRenderingInfo rendering{VK_STRUCTURE_TYPE_RENDERING_INFO};
      rendering.renderArea = {{0, 0}, {width, height}};
      rendering.layerCount = 1;
      rendering.colorAttachmentCount = uint32_t(colors.size());
      rendering.pColorAttachments = colors.data();
      vkCmdBeginRendering(cmd, &rendering);
      VkViewport viewport{0, 0, float(width), float(height), 0, 1};
      VkRect2D scissor{{0, 0}, {width, height}};
      vkCmdSetViewport(cmd, 0, 1, &viewport);
      vkCmdSetScissor(cmd, 0, 1, &scissor);
      vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pso.pipeline);
      if (bind) bind(cmd);  // descriptor sets, push constants
      vkCmdDraw(cmd, 3, 1, 0, 0);
      vkCmdEndRendering(cmd);
      for (size_t i = 0; i < out.images.size(); ++i) {
        VkImage image = out.images[i]->image;
        bootstrap::image_barrier(cmd, image, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                                 VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT,
                                 VK_ACCESS_TRANSFER_READ_BIT, VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT,
                                 VK_PIPELINE_STAGE_TRANSFER_BIT);
        VkBufferImageCopy copy{};
        copy.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
        copy.imageExtent = {width, height, 1};
        vkCmdCopyImageToBuffer(cmd, image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, readbacks[i]->buffer, 1,
                               &copy);
        bootstrap::image_barrier(cmd, image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                                 VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, VK_ACCESS_TRANSFER_READ_BIT,
                                 VK_ACCESS_SHADER_READ_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT,
                                 VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT);
      }
    });
    EXPECT_TRUE(submitted) << submitted.error().message;
    for (size_t i = 0; i < readbacks.size(); ++i) {
      const auto* bytes = static_cast<const uint8_t*>(readbacks[i]->mapped);
      out.pixels.emplace_back(bytes, bytes + size_t(width) * height * targets[i].bytes_per_pixel);
    }
    return out;
  }

  // Runs a compute pipeline once (one work group) with a 16-byte host-visible storage buffer, filled with
  // `fill` first, bound where the pipeline's binding `buffer_name` is; returns the buffer's bytes after.
  std::array<uint8_t, 16> dispatch_once(const UnpackedPipeline& pso, std::string_view buffer_name,
                                        uint8_t fill = 0) {
    std::array<uint8_t, 16> out{};
    auto buffer = bootstrap::create_host_buffer(*vk_, out.size(), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
    EXPECT_TRUE(buffer);
    const BindingInfo* binding = pso.find_binding(buffer_name);
    EXPECT_NE(binding, nullptr) << buffer_name;
    if (!buffer || !binding) return out;
    std::memset((*buffer)->mapped, fill, out.size());
    auto set = bootstrap::bind_storage_buffer(*vk_, pso.set_layouts.at(binding->set), binding->binding,
                                              (*buffer)->buffer);
    EXPECT_TRUE(set);
    if (!set) return out;
    auto done = vk_->submit_and_wait([&](VkCommandBuffer cmd) {
      vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pso.pipeline);
      vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pso.layout, binding->set, 1, &(*set)->set,
                              0, nullptr);
      vkCmdDispatch(cmd, 1, 1, 1);
    });
    EXPECT_TRUE(done);
    std::memcpy(out.data(), (*buffer)->mapped, out.size());
    return out;
  }

  // The same into one image of `format` (4 bytes per pixel), returning its bytes.
  std::vector<uint8_t> render_fullscreen(const UnpackedPipeline& pso, VkFormat format, uint32_t width,
                                         uint32_t height,
                                         const std::function<void(VkCommandBuffer)>& bind = {}) {
    const TargetFormat target{format, 4};
    RenderedTargets rendered = render_targets(pso, std::span(&target, 1), width, height, bind);
    return rendered.pixels.empty() ? std::vector<uint8_t>{} : std::move(rendered.pixels[0]);
  }

  std::unique_ptr<bootstrap::VulkanContext> vk_;
};

}  // namespace statepack::testing
