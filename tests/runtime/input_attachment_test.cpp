// Input attachments are read from a render pass's subpass: a pipeline in a subpass that lists them
// unpacks on lavapipe without a validation message, and an archive that takes its render pass away
// (dynamic rendering, which has no input attachments: VUID-VkGraphicsPipelineCreateInfo-renderPass-06061)
// is refused at load, naming the pipeline, the shader and the binding. `statepack pack` refuses the
// same at the shader slot (tests/corpus/invalid/input_attachment_without_render_pass.json).
#include "common/forged_archive.hpp"
#include "common/vulkan_test_fixture.hpp"
#include "runtime/archive_access.hpp"

namespace statepack::testing {
namespace {

class InputAttachmentTest : public VulkanTest {};

TEST_F(InputAttachmentTest, ASubpassInputInItsRenderPassUnpacks) {
  auto archive = Archive::from_file(STATEPACK_INPUT_ATTACHMENT_ARCHIVE);
  ASSERT_TRUE(archive) << archive.error().message;
  auto dearchiver = Dearchiver::create(vk_->device_context());
  ASSERT_TRUE(dearchiver);
  ASSERT_TRUE(dearchiver->add_archive(std::move(*archive)));
  auto pso = dearchiver->unpack_graphics("Tonemap PSO");
  ASSERT_TRUE(pso) << pso.error().message;
  // The application writes the attachment's view into this binding of the subpass's pipeline.
  const BindingInfo* hdr = (*pso)->find_binding("hdr");
  ASSERT_NE(hdr, nullptr);
  EXPECT_EQ(hdr->type, VK_DESCRIPTOR_TYPE_INPUT_ATTACHMENT);
  EXPECT_EQ(hdr->set, 0u);
  EXPECT_EQ(hdr->binding, 0u);
  EXPECT_EQ(hdr->stages, VkShaderStageFlags(VK_SHADER_STAGE_FRAGMENT_BIT));
  EXPECT_TRUE(dearchiver->unpack_render_pass("Tonemap Pass"));
}

TEST_F(InputAttachmentTest, WithoutARenderPassTheArchiveIsRefusedAtLoad) {
  auto archive = Archive::from_file(STATEPACK_INPUT_ATTACHMENT_ARCHIVE);
  ASSERT_TRUE(archive) << archive.error().message;
  format::Contents c = detail::ArchiveAccess::contents(*archive);
  ASSERT_EQ(c.pipelines.size(), 1u);
  c.pipelines[0].render_pass = format::kNone;
  c.pipelines[0].subpass = 0;
  ForgedBytes bytes(format::encode(c));
  auto forged = Archive::from_memory(bytes.span());
  ASSERT_FALSE(forged);
  EXPECT_EQ(
      forged.error().message,
      "archive in memory: corrupt archive: pipeline 'Tonemap PSO': shader 'Tonemap PS' reads an input "
      "attachment (set 0, binding 0), but the pipeline has no render pass, and dynamic rendering has no "
      "input attachments");
}

}  // namespace
}  // namespace statepack::testing
