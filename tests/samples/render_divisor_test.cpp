// The window's moving frames (Renderer::set_render_divisor): traced at a fraction of the size and shown
// as blocks of that size, and once the view is still again the accumulation starts over at the full size
// and converges to exactly the image that never moved. On lavapipe with the validation layer on.
#include <gtest/gtest.h>

#include <vector>

#include "path_tracer/app.hpp"
#include "path_tracer/scene.hpp"
#include "statepack/bootstrap/vulkan_context.hpp"

namespace statepack::testing {
namespace {

using namespace path_tracer;

constexpr uint32_t kWidth = 64, kHeight = 48;
constexpr VkFormat kTarget = VK_FORMAT_R8G8B8A8_UNORM;

class RenderDivisor : public ::testing::Test {
 protected:
  void SetUp() override {
    auto vk = bootstrap::VulkanContext::create({});
    ASSERT_TRUE(vk) << vk.error().message;
    vk_ = std::move(vk.value());
    dearchiver_ = load_archive(*vk_, STATEPACK_PATH_TRACER_ARCHIVE);
    ASSERT_TRUE(dearchiver_);
    auto scene = load_scene(STATEPACK_DEFAULT_SCENE);
    ASSERT_TRUE(scene) << scene.error().message;
    scene_ = *scene;
    auto target =
        bootstrap::create_device_image(*vk_, kTarget, kWidth, kHeight,
                                       VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT);
    ASSERT_TRUE(target) << target.error().message;
    target_ = std::move(target.value());
  }
  void TearDown() override {
    target_.reset();
    dearchiver_.reset();
    if (!vk_) return;
    vk_->destroy_device();
    EXPECT_EQ(report_validation(*vk_), 0u) << "validation messages";
  }

  std::unique_ptr<Renderer> renderer() {
    auto r = Renderer::create(*vk_, *dearchiver_, kWidth, kHeight, kTarget);
    EXPECT_TRUE(r) << r.error().message;
    EXPECT_TRUE((*r)->set_scene(scene_));
    RenderSettings s;
    s.samples_per_frame = 2;
    (*r)->set_settings(s);
    return std::move(r.value());
  }
  void frame(Renderer& r) {
    auto done = vk_->submit_and_wait([&](VkCommandBuffer cmd) {
      r.record(cmd, target_->image, target_->view, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
    });
    ASSERT_TRUE(done) << done.error().message;
  }
  // What the last frame resolved into the target, RGBA8 rows.
  std::vector<uint8_t> shown() {
    auto buffer = bootstrap::create_host_buffer(*vk_, VkDeviceSize(kWidth) * kHeight * 4,
                                                VK_BUFFER_USAGE_TRANSFER_DST_BIT);
    EXPECT_TRUE(buffer);
    auto done = vk_->submit_and_wait([&](VkCommandBuffer cmd) {
      VkBufferImageCopy copy{};
      copy.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
      copy.imageExtent = {kWidth, kHeight, 1};
      vkCmdCopyImageToBuffer(cmd, target_->image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, (*buffer)->buffer, 1,
                             &copy);
    });
    EXPECT_TRUE(done);
    const auto* bytes = static_cast<const uint8_t*>((*buffer)->mapped);
    return {bytes, bytes + size_t(kWidth) * kHeight * 4};
  }

  std::unique_ptr<bootstrap::VulkanContext> vk_;
  std::unique_ptr<Dearchiver> dearchiver_;
  Scene scene_;
  std::unique_ptr<bootstrap::DeviceImage> target_;
};

TEST_F(RenderDivisor, MovingFramesAreTracedSmallerAndShownInBlocks) {
  auto r = renderer();
  r->set_render_divisor(2);
  EXPECT_EQ(r->render_width(), kWidth / 2);
  EXPECT_EQ(r->render_height(), kHeight / 2);
  frame(*r);
  const std::vector<uint8_t> pixels = shown();
  size_t lit = 0;
  for (uint32_t y = 0; y < kHeight; y += 2)
    for (uint32_t x = 0; x < kWidth; x += 2)
      for (uint32_t c = 0; c < 3; ++c) {
        const uint8_t v = pixels[(size_t(y) * kWidth + x) * 4 + c];
        lit += v > 0;
        ASSERT_EQ(pixels[(size_t(y) * kWidth + x + 1) * 4 + c], v) << x << "," << y;
        ASSERT_EQ(pixels[(size_t(y + 1) * kWidth + x) * 4 + c], v) << x << "," << y;
        ASSERT_EQ(pixels[(size_t(y + 1) * kWidth + x + 1) * 4 + c], v) << x << "," << y;
      }
  EXPECT_GT(lit, size_t(kWidth * kHeight / 4));  // the room, not a black image
  r->set_render_divisor(100);                    // clamped: at most 1/8
  EXPECT_EQ(r->render_divisor(), 8u);
}

TEST_F(RenderDivisor, StillFramesConvergeToTheImageThatNeverMoved) {
  auto still = renderer();
  for (int i = 0; i < 4; ++i) frame(*still);
  auto expected = still->read_accumulation();
  ASSERT_TRUE(expected) << expected.error().message;

  auto moved = renderer();
  moved->set_render_divisor(3);  // a few moving frames at a third of the size
  for (int i = 0; i < 3; ++i) frame(*moved);
  EXPECT_EQ(moved->samples_done(), 6u);
  moved->set_render_divisor(1);  // still again: the accumulation starts over at the full size
  EXPECT_EQ(moved->samples_done(), 0u);
  for (int i = 0; i < 4; ++i) frame(*moved);
  auto got = moved->read_accumulation();
  ASSERT_TRUE(got) << got.error().message;
  ASSERT_EQ(got->size(), expected->size());
  EXPECT_TRUE(*got == *expected) << "the image differs from the one rendered without moving";
}

}  // namespace
}  // namespace statepack::testing
