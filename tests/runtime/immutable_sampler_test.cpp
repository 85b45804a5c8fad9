// Immutable samplers reach Vulkan: the archive's sampler (point filtering, repeat addressing) is baked
// into the set layout, the application writes only the image, and the pixels show that sampler's
// behaviour, which no default sampler has.
#include <array>
#include <cstring>

#include "common/vulkan_test_fixture.hpp"

namespace statepack::testing {
namespace {

class ImmutableSamplerTest : public VulkanTest {};

TEST_F(ImmutableSamplerTest, SamplesThroughTheArchivedSamplerWithNoSamplerWritten) {
  auto dearchiver = Dearchiver::create({vk_->physical_device, vk_->device});
  ASSERT_TRUE(dearchiver);
  auto archive = Archive::from_file(STATEPACK_IMMUTABLE_SAMPLER_ARCHIVE);
  ASSERT_TRUE(archive) << archive.error().message;
  ASSERT_TRUE(dearchiver->add_archive(std::move(*archive)));
  auto pso = dearchiver->unpack_graphics("Wrapped Checker PSO");
  ASSERT_TRUE(pso) << pso.error().message;
  const BindingInfo* checker = (*pso)->find_binding("checker");
  ASSERT_NE(checker, nullptr);
  EXPECT_EQ(checker->type, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER);
  ASSERT_NE(checker->immutable_sampler, VK_NULL_HANDLE);
  // The signature unpacked by name shares the layout and reports the same sampler.
  auto signature = dearchiver->unpack_signature("Checker Signature");
  ASSERT_TRUE(signature) << signature.error().message;
  EXPECT_EQ((*signature)->layout, (*pso)->set_layouts.at(checker->set));
  EXPECT_EQ((*signature)->bindings.at(0).immutable_sampler, checker->immutable_sampler);

  // A 2x2 texture: red, green / blue, white.
  const std::array<std::array<uint8_t, 4>, 4> texels = {
      {{255, 0, 0, 255}, {0, 255, 0, 255}, {0, 0, 255, 255}, {255, 255, 255, 255}}};
  auto texture = bootstrap::create_device_image(*vk_, VK_FORMAT_R8G8B8A8_UNORM, 2, 2,
                                                VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT);
  ASSERT_TRUE(texture) << texture.error().message;
  auto upload = bootstrap::create_host_buffer(*vk_, sizeof texels, VK_BUFFER_USAGE_TRANSFER_SRC_BIT);
  ASSERT_TRUE(upload);
  std::memcpy((*upload)->mapped, texels.data(), sizeof texels);
  auto uploaded = vk_->submit_and_wait([&](VkCommandBuffer cmd) {
    bootstrap::image_barrier(cmd, (*texture)->image, VK_IMAGE_LAYOUT_UNDEFINED,
                             VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 0, VK_ACCESS_TRANSFER_WRITE_BIT,
                             VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT);
    VkBufferImageCopy copy{};
    copy.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    copy.imageExtent = {2, 2, 1};
    vkCmdCopyBufferToImage(cmd, (*upload)->buffer, (*texture)->image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1,
                           &copy);
    bootstrap::image_barrier(cmd, (*texture)->image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                             VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, VK_ACCESS_TRANSFER_WRITE_BIT,
                             VK_ACCESS_SHADER_READ_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT,
                             VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT);
  });
  ASSERT_TRUE(uploaded) << uploaded.error().message;

  // The descriptor names the image only: the sampler comes from the layout.
  VkDescriptorPoolSize pool_size{VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1};
  VkDescriptorPoolCreateInfo pool_info{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
  pool_info.maxSets = 1;
  pool_info.poolSizeCount = 1;
  pool_info.pPoolSizes = &pool_size;
  VkDescriptorPool pool = VK_NULL_HANDLE;
  ASSERT_EQ(vkCreateDescriptorPool(vk_->device, &pool_info, nullptr, &pool), VK_SUCCESS);
  VkDescriptorSetLayout layout = (*pso)->set_layouts.at(checker->set);
  VkDescriptorSetAllocateInfo alloc{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
  alloc.descriptorPool = pool;
  alloc.descriptorSetCount = 1;
  alloc.pSetLayouts = &layout;
  VkDescriptorSet set = VK_NULL_HANDLE;
  ASSERT_EQ(vkAllocateDescriptorSets(vk_->device, &alloc, &set), VK_SUCCESS);
  VkDescriptorImageInfo image_info{VK_NULL_HANDLE, (*texture)->view,
                                   VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
  VkWriteDescriptorSet write{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
  write.dstSet = set;
  write.dstBinding = checker->binding;
  write.descriptorCount = 1;
  write.descriptorType = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
  write.pImageInfo = &image_info;
  vkUpdateDescriptorSets(vk_->device, 1, &write, 0, nullptr);

  constexpr uint32_t kSize = 8;
  auto pixels = render_fullscreen(**pso, VK_FORMAT_R8G8B8A8_UNORM, kSize, kSize, [&](VkCommandBuffer cmd) {
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, (*pso)->layout, checker->set, 1, &set, 0,
                            nullptr);
  });
  vkDestroyDescriptorPool(vk_->device, pool, nullptr);
  ASSERT_EQ(pixels.size(), size_t(kSize) * kSize * 4);
  // uv * 2 spans the texture twice: point sampling with repeat gives texel ((x / 2) % 2, (y / 2) % 2).
  // Clamping would give the right column from x = 4 on, linear filtering blended colours.
  for (uint32_t y = 0; y < kSize; ++y)
    for (uint32_t x = 0; x < kSize; ++x) {
      const auto& want = texels[((y / 2) % 2) * 2 + (x / 2) % 2];
      const uint8_t* got = &pixels[(size_t(y) * kSize + x) * 4];
      for (int c = 0; c < 4; ++c)
        ASSERT_EQ(got[c], want[c]) << "pixel (" << x << ", " << y << ") channel " << c;
    }
}

}  // namespace
}  // namespace statepack::testing
