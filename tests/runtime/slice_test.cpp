// The vertical slice on lavapipe: pipelines from the archive dispatch and draw, and the results are read
// back and checked.
#include <cmath>
#include <cstring>
#include <fstream>
#include <vector>

#include "common/vulkan_test_fixture.hpp"
#include "format/archive_format.hpp"
#include "runtime/archive_access.hpp"

namespace statepack::testing {
namespace {

using bootstrap::create_host_buffer;

class SliceTest : public VulkanTest {
 protected:
  // The gradient shader writes (u, v, 0.25, 1) with u, v the pixel centre in 0..1.
  static std::array<int, 4> expected_rgba(uint32_t x, uint32_t y, uint32_t width, uint32_t height) {
    auto unorm = [](double v) { return int(std::lround(v * 255.0)); };
    return {unorm((x + 0.5) / width), unorm((y + 0.5) / height), unorm(0.25), 255};
  }
};

TEST_F(SliceTest, ComputePipelineFillsBuffer) {
  Dearchiver dearchiver = make_dearchiver();
  auto pso = dearchiver.unpack_compute("Fill Buffer PSO");
  ASSERT_TRUE(pso) << pso.error().message;
  const BindingInfo* values = (*pso)->find_binding("Values");
  ASSERT_NE(values, nullptr);
  EXPECT_EQ(values->type, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER);
  EXPECT_EQ(values->stages, VkShaderStageFlags(VK_SHADER_STAGE_COMPUTE_BIT));
  EXPECT_EQ((*pso)->push_constant_size, 12u);

  constexpr uint32_t kCount = 1000;  // not a multiple of the 64-wide workgroup: the bound check matters
  auto buffer =
      create_host_buffer(*vk_, (kCount + 24) * sizeof(uint32_t), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
  ASSERT_TRUE(buffer);
  std::memset((*buffer)->mapped, 0xAB, (*buffer)->size);

  auto set = bootstrap::bind_storage_buffer(*vk_, (*pso)->set_layouts.at(values->set), values->binding,
                                            (*buffer)->buffer);
  ASSERT_TRUE(set) << set.error().message;

  const uint32_t params[3] = {kCount, 7, 5};
  auto done = vk_->submit_and_wait([&](VkCommandBuffer cmd) {
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, (*pso)->pipeline);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, (*pso)->layout, values->set, 1, &(*set)->set,
                            0, nullptr);
    vkCmdPushConstants(cmd, (*pso)->layout, (*pso)->push_constant_stages, 0, sizeof params, params);
    vkCmdDispatch(cmd, (kCount + 63) / 64, 1, 1);
  });
  ASSERT_TRUE(done) << done.error().message;
  const auto* out = static_cast<const uint32_t*>((*buffer)->mapped);
  for (uint32_t i = 0; i < kCount; ++i) ASSERT_EQ(out[i], i * 7 + 5) << "at index " << i;
  EXPECT_EQ(out[kCount], 0xABABABABu) << "the shader wrote past params.count";
}

TEST_F(SliceTest, GraphicsPipelineDrawsGradient) {
  Dearchiver dearchiver = make_dearchiver();
  auto pso = dearchiver.unpack_graphics("Gradient PSO");
  ASSERT_TRUE(pso) << pso.error().message;
  constexpr uint32_t kWidth = 64, kHeight = 48;
  auto pixels = render_fullscreen(**pso, VK_FORMAT_R8G8B8A8_UNORM, kWidth, kHeight);
  ASSERT_EQ(pixels.size(), size_t(kWidth) * kHeight * 4);
  for (uint32_t y = 0; y < kHeight; ++y) {
    for (uint32_t x = 0; x < kWidth; ++x) {
      auto want = expected_rgba(x, y, kWidth, kHeight);
      const uint8_t* got = &pixels[(size_t(y) * kWidth + x) * 4];
      for (int c = 0; c < 4; ++c)
        ASSERT_NEAR(got[c], want[c], 1) << "pixel (" << x << ", " << y << ") channel " << c;
    }
  }
}

TEST_F(SliceTest, ModifyCallbackPatchesRenderTargetFormat) {
  Dearchiver dearchiver = make_dearchiver();
  bool called = false;
  auto pso = dearchiver.unpack_graphics("Gradient PSO", [&](PatchableState& state) {
    called = true;
    EXPECT_EQ(state.color_count, 1u);
    EXPECT_EQ(state.color_formats[0], VK_FORMAT_R8G8B8A8_UNORM);  // as packed
    state.color_formats[0] = VK_FORMAT_B8G8R8A8_UNORM;            // what a swapchain often has
  });
  ASSERT_TRUE(pso) << pso.error().message;
  EXPECT_TRUE(called);
  constexpr uint32_t kWidth = 16, kHeight = 16;
  auto pixels = render_fullscreen(**pso, VK_FORMAT_B8G8R8A8_UNORM, kWidth, kHeight);
  // Same colours, stored blue-first: proves the pipeline really targets the patched format.
  for (uint32_t y = 0; y < kHeight; ++y) {
    for (uint32_t x = 0; x < kWidth; ++x) {
      auto want = expected_rgba(x, y, kWidth, kHeight);
      const uint8_t* got = &pixels[(size_t(y) * kWidth + x) * 4];
      ASSERT_NEAR(got[0], want[2], 1);
      ASSERT_NEAR(got[1], want[1], 1);
      ASSERT_NEAR(got[2], want[0], 1);
      ASSERT_NEAR(got[3], want[3], 1);
    }
  }
  // A patched pipeline is a new object; the unpatched one is cached and shared.
  auto plain1 = dearchiver.unpack_graphics("Gradient PSO");
  auto plain2 = dearchiver.unpack_graphics("Gradient PSO");
  ASSERT_TRUE(plain1 && plain2);
  EXPECT_EQ(*plain1, *plain2);
  EXPECT_NE((*plain1)->pipeline, (*pso)->pipeline);
}

TEST_F(SliceTest, RunTimeFormatsLeftUnknownAreErrors) {
  // The slice archive with its gradient target made UNKNOWN ("patched at run time").
  auto original = Archive::from_file(STATEPACK_TEST_ARCHIVE);
  ASSERT_TRUE(original);
  format::Contents contents = detail::ArchiveAccess::contents(*original);
  for (auto& p : contents.pipelines)
    if (p.name == "Gradient PSO") p.graphics.color_formats[0] = VK_FORMAT_UNDEFINED;
  std::vector<uint8_t> bytes = format::encode(contents);
  std::vector<uint32_t> words((bytes.size() + 3) / 4);
  std::memcpy(words.data(), bytes.data(), bytes.size());
  auto archive = Archive::from_memory({reinterpret_cast<const uint8_t*>(words.data()), bytes.size()});
  ASSERT_TRUE(archive) << archive.error().message;
  auto dearchiver = Dearchiver::create({vk_->physical_device, vk_->device});
  ASSERT_TRUE(dearchiver);
  ASSERT_TRUE(dearchiver->add_archive(std::move(*archive)));
  auto unpatched = dearchiver->unpack_graphics("Gradient PSO");
  ASSERT_FALSE(unpatched);
  EXPECT_EQ(
      unpatched.error().message,
      "pipeline 'Gradient PSO': render target 0 is UNKNOWN (a format set at run time); set "
      "PatchableState::color_formats[0] in the modify callback, or give RTVFormats[0] in the notation and "
      "pack again");
  auto patched = dearchiver->unpack_graphics(
      "Gradient PSO", [](PatchableState& s) { s.color_formats[0] = VK_FORMAT_B8G8R8A8_UNORM; });
  ASSERT_TRUE(patched) << patched.error().message;
}

TEST_F(SliceTest, UnknownNameIsAnErrorWithSuggestion) {
  Dearchiver dearchiver = make_dearchiver();
  auto pso = dearchiver.unpack_graphics("Gradient PS0");
  ASSERT_FALSE(pso);
  EXPECT_EQ(pso.error().code, ErrorCode::not_found);
  EXPECT_NE(pso.error().message.find("did you mean 'Gradient PSO'"), std::string::npos)
      << pso.error().message;
}

TEST_F(SliceTest, WrongPipelineTypeIsAnError) {
  Dearchiver dearchiver = make_dearchiver();
  auto pso = dearchiver.unpack_compute("Gradient PSO");
  ASSERT_FALSE(pso);
  EXPECT_EQ(pso.error().code, ErrorCode::wrong_type);
  EXPECT_NE(pso.error().message.find("graphics"), std::string::npos) << pso.error().message;
}

TEST_F(SliceTest, ArchiveFromCallerMemoryUnpacks) {
  std::ifstream file(STATEPACK_TEST_ARCHIVE, std::ios::binary);
  std::vector<char> chars((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  std::vector<uint32_t> words((chars.size() + 3) / 4);  // 4-byte aligned, as the API requires
  std::memcpy(words.data(), chars.data(), chars.size());
  auto archive = Archive::from_memory({reinterpret_cast<const uint8_t*>(words.data()), chars.size()});
  ASSERT_TRUE(archive) << archive.error().message;
  // Zero copy: the SPIR-V the dearchiver hands Vulkan lies inside the caller's buffer.
  auto blob = detail::ArchiveAccess::contents(*archive).spirv.at(0);
  EXPECT_GE(reinterpret_cast<const uint8_t*>(blob.data()), reinterpret_cast<const uint8_t*>(words.data()));
  EXPECT_LT(reinterpret_cast<const uint8_t*>(blob.data()),
            reinterpret_cast<const uint8_t*>(words.data()) + chars.size());
  auto dearchiver = Dearchiver::create({vk_->physical_device, vk_->device});
  ASSERT_TRUE(dearchiver);
  ASSERT_TRUE(dearchiver->add_archive(std::move(*archive)));
  auto pso = dearchiver->unpack_compute("Fill Buffer PSO");
  ASSERT_TRUE(pso) << pso.error().message;
  EXPECT_NE((*pso)->pipeline, VK_NULL_HANDLE);
}

}  // namespace
}  // namespace statepack::testing
