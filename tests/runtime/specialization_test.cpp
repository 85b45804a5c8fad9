// Specialization constants: two pipelines that differ only in constants share one SPIR-V blob and give
// two results on lavapipe, and the modify callback overrides a constant by name (sizes checked).
#include <cstring>

#include "common/vulkan_test_fixture.hpp"
#include "format/archive_format.hpp"
#include "runtime/archive_access.hpp"

namespace statepack::testing {
namespace {

class SpecializationTest : public VulkanTest {
 protected:
  Dearchiver load() {
    auto dearchiver = Dearchiver::create({vk_->physical_device, vk_->device});
    EXPECT_TRUE(dearchiver);
    auto archive = Archive::from_file(STATEPACK_SPECIALIZATION_ARCHIVE);
    EXPECT_TRUE(archive) << archive.error().message;
    EXPECT_TRUE(dearchiver->add_archive(std::move(*archive)));
    return std::move(*dearchiver);
  }
  // Runs the pipeline once; returns what the shader wrote: (value, scaled).
  std::pair<uint32_t, float> run(const UnpackedPipeline& pso) {
    const std::array<uint8_t, 16> bytes = dispatch_once(pso, "Result");
    std::pair<uint32_t, float> out;
    std::memcpy(&out.first, bytes.data(), 4);
    std::memcpy(&out.second, bytes.data() + 4, 4);
    return out;
  }
};

TEST_F(SpecializationTest, PipelinesDifferingOnlyInConstantsShareOneBlobAndGiveTheirOwnResults) {
  Dearchiver dearchiver = load();
  auto archive = Archive::from_file(STATEPACK_SPECIALIZATION_ARCHIVE);
  ASSERT_TRUE(archive);
  const format::Contents& c = detail::ArchiveAccess::contents(*archive);
  ASSERT_EQ(c.pipelines.size(), 2u);
  EXPECT_EQ(c.spirv.size(), 1u);  // one module for both pipelines (and the standalone shader)
  EXPECT_EQ(c.shaders[c.pipelines[0].shaders[0]].blob, c.shaders[c.pipelines[1].shaders[0]].blob);

  auto seven = dearchiver.unpack_compute("Seven");
  ASSERT_TRUE(seven) << seven.error().message;
  EXPECT_EQ(run(**seven), std::pair(7u, 3.0f));  // kBase 7, kScale 1.5 (times 2)
  auto negated = dearchiver.unpack_compute("Negated");
  ASSERT_TRUE(negated) << negated.error().message;
  EXPECT_EQ(run(**negated), std::pair(958u, 2.0f));  // kNegate: 1000 - 42; kScale keeps the shader's 1.0
}

TEST_F(SpecializationTest, TheModifyCallbackReadsAndOverridesConstantsByName) {
  Dearchiver dearchiver = load();
  bool called = false;
  auto overridden = dearchiver.unpack_compute("Seven", [&](PatchableState& s) {
    called = true;
    ASSERT_EQ(s.constants.size(), 2u);
    const SpecializationConstant* base = s.find_constant("kBase");
    ASSERT_NE(base, nullptr);
    EXPECT_EQ(base->get<uint32_t>(), 7u);
    EXPECT_EQ(base->stages, VkShaderStageFlags(VK_SHADER_STAGE_COMPUTE_BIT));
    EXPECT_EQ(s.find_constant("kScale")->get<float>(), 1.5f);
    EXPECT_FALSE(s.set_constant("kBase", uint64_t{5}));  // 8 bytes for a 4-byte uint: refused
    EXPECT_FALSE(s.set_constant("kMissing", 1u));
    EXPECT_TRUE(s.set_constant("kBase", 123u));
  });
  ASSERT_TRUE(overridden) << overridden.error().message;
  EXPECT_TRUE(called);
  EXPECT_EQ(run(**overridden), std::pair(123u, 3.0f));
  // The archived pipeline is unchanged by the override.
  auto plain = dearchiver.unpack_compute("Seven");
  ASSERT_TRUE(plain);
  EXPECT_NE((*plain)->pipeline, (*overridden)->pipeline);
  EXPECT_EQ(run(**plain), std::pair(7u, 3.0f));

  // A callback that changes a constant's size, or adds one, is an error naming it.
  auto resized = dearchiver.unpack_compute("Seven", [](PatchableState& s) { s.constants[0].size = 8; });
  ASSERT_FALSE(resized);
  EXPECT_EQ(resized.error().message,
            "pipeline 'Seven': specialization constant 'kBase' is 4 bytes, but the modify callback gave 8");
  auto added =
      dearchiver.unpack_compute("Seven", [](PatchableState& s) { s.constants.push_back({"kOther"}); });
  ASSERT_FALSE(added);
  EXPECT_EQ(added.error().message,
            "pipeline 'Seven' has no specialization constant 'kOther' (the modify callback added it)");
}

}  // namespace
}  // namespace statepack::testing
