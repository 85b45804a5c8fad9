// A notation with every pack-time interface check satisfied (two vertex buffers, integer and float
// varyings, blending, a depth-only pipeline, an HLSL compute shader) packs, and its forward pipeline
// draws the expected pixels on lavapipe with the validation layer on: the checks accept what is right,
// not only refuse what is wrong.
#include <array>
#include <cstring>

#include "common/vulkan_test_fixture.hpp"

namespace statepack::testing {
namespace {

class CheckedInterfacesTest : public VulkanTest {};

TEST_F(CheckedInterfacesTest, ForwardPipelineDrawsFromTwoVertexBuffersWithBlending) {
  auto dearchiver = Dearchiver::create({vk_->physical_device, vk_->device});
  ASSERT_TRUE(dearchiver);
  auto archive = Archive::from_file(STATEPACK_CHECKED_INTERFACES_ARCHIVE);
  ASSERT_TRUE(archive) << archive.error().message;
  ASSERT_TRUE(dearchiver->add_archive(std::move(*archive)));
  auto shadow = dearchiver->unpack_graphics("Shadow PSO");  // depth only: no pixel shader, no target
  ASSERT_TRUE(shadow) << shadow.error().message;
  auto blur = dearchiver->unpack_compute("Blur PSO");
  ASSERT_TRUE(blur) << blur.error().message;
  auto pso = dearchiver->unpack_graphics("Forward PSO");
  ASSERT_TRUE(pso) << pso.error().message;

  // A triangle covering the screen; per vertex: RGBA8 color, then a 32-bit id, in slot 1.
  const std::array<float, 6> positions = {-1, -1, 3, -1, -1, 3};
  struct Attributes {
    std::array<uint8_t, 4> color;
    uint32_t id;
  };
  const std::array<Attributes, 3> attributes = {
      {{{255, 0, 0, 255}, 2}, {{255, 0, 0, 255}, 2}, {{255, 0, 0, 255}, 2}}};
  auto position_buffer =
      bootstrap::create_host_buffer(*vk_, sizeof positions, VK_BUFFER_USAGE_VERTEX_BUFFER_BIT);
  auto attribute_buffer =
      bootstrap::create_host_buffer(*vk_, sizeof attributes, VK_BUFFER_USAGE_VERTEX_BUFFER_BIT);
  ASSERT_TRUE(position_buffer && attribute_buffer);
  std::memcpy((*position_buffer)->mapped, positions.data(), sizeof positions);
  std::memcpy((*attribute_buffer)->mapped, attributes.data(), sizeof attributes);

  constexpr uint32_t kSize = 4;
  std::vector<uint8_t> pixels =
      render_fullscreen(**pso, VK_FORMAT_R8G8B8A8_UNORM, kSize, kSize, [&](VkCommandBuffer cmd) {
        const VkBuffer buffers[] = {(*position_buffer)->buffer, (*attribute_buffer)->buffer};
        const VkDeviceSize offsets[] = {0, 0};
        vkCmdBindVertexBuffers(cmd, 0, 2, buffers, offsets);
      });
  ASSERT_EQ(pixels.size(), kSize * kSize * 4u);
  // red = 1.0 * id 2 * 0.5 = 1, alpha 0.5, blended SRC_ALPHA / INV_SRC_ALPHA over cleared black:
  // 0.5 red; alpha ONE / ZERO: 0.5.
  for (size_t i = 0; i < pixels.size(); i += 4) {
    EXPECT_NEAR(pixels[i + 0], 128, 1) << "pixel " << i / 4;
    EXPECT_EQ(pixels[i + 1], 0) << "pixel " << i / 4;
    EXPECT_EQ(pixels[i + 2], 0) << "pixel " << i / 4;
    EXPECT_NEAR(pixels[i + 3], 128, 1) << "pixel " << i / 4;
  }
}

}  // namespace
}  // namespace statepack::testing
