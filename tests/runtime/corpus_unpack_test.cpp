// Every object of every corpus archive becomes a valid Vulkan object on lavapipe: pipelines (with
// signatures, render passes, immutable samplers, vertex input), signatures, render passes and
// standalone shaders, with the validation layer silent.
#include <algorithm>
#include <bit>
#include <sstream>

#include "common/vulkan_test_fixture.hpp"
#include "format/archive_format.hpp"
#include "runtime/archive_access.hpp"

namespace statepack::testing {
namespace {

class CorpusUnpack : public VulkanTest {
 protected:
  // An unpacked binding matches the archived one in every field, and carries a sampler exactly where
  // the archive stores an immutable sampler.
  static void expect_binding(const BindingInfo& got, const format::Binding& want, uint32_t set,
                             const std::string& owner) {
    SCOPED_TRACE(owner + ": binding '" + want.name + "'");
    EXPECT_EQ(got.name, want.name);
    EXPECT_EQ(got.set, set);
    EXPECT_EQ(got.binding, want.binding);
    EXPECT_EQ(got.type, static_cast<VkDescriptorType>(want.descriptor_type));
    EXPECT_EQ(got.count, want.count);
    EXPECT_EQ(got.stages, want.stage_flags);
    EXPECT_EQ(got.immutable_sampler != VK_NULL_HANDLE, want.immutable_sampler != format::kNone);
  }
};

TEST_F(CorpusUnpack, EveryObjectOfEveryArchiveUnpacks) {
  auto archives = corpus_archives();
  ASSERT_GE(archives.size(), 5u);
  size_t pipelines = 0, signatures = 0, passes = 0, shaders = 0, run_time_targets = 0;
  for (const auto& path : archives) {
    SCOPED_TRACE(path);
    auto archive = Archive::from_file(path);
    ASSERT_TRUE(archive) << archive.error().message;
    format::Contents contents =
        detail::ArchiveAccess::contents(*archive);  // names only; the archive moves below
    auto dearchiver = Dearchiver::create(vk_->device_context());
    ASSERT_TRUE(dearchiver);
    ASSERT_TRUE(dearchiver->add_archive(std::move(*archive)));
    for (const auto& p : contents.pipelines) {
      auto pso = p.kind == format::PipelineKind::compute ? dearchiver->unpack_compute(p.name)
                                                         : dearchiver->unpack_graphics(p.name);
      if (!pso && pso.error().message.find("the notation leaves them to run time") != std::string::npos) {
        // Render targets left to the application (Diligent's workflow): refused unpatched, as it must
        // be, and created once the callback sets them as verify does.
        EXPECT_EQ(pso.error().code, ErrorCode::invalid_argument);
        pso = dearchiver->unpack_graphics(p.name, [](PatchableState& s) {
          s.color_count = std::max<uint32_t>(s.color_count, 32 - std::countl_zero(s.written_color_targets));
          for (uint32_t i = 0; i < s.color_count; ++i)
            if (s.color_formats[i] == VK_FORMAT_UNDEFINED) s.color_formats[i] = VK_FORMAT_R8G8B8A8_UNORM;
        });
        ++run_time_targets;
      }
      ASSERT_TRUE(pso) << p.name << ": " << pso.error().message;
      EXPECT_NE((*pso)->pipeline, VK_NULL_HANDLE);
      EXPECT_EQ((*pso)->bind_point, p.kind == format::PipelineKind::compute
                                        ? VK_PIPELINE_BIND_POINT_COMPUTE
                                        : VK_PIPELINE_BIND_POINT_GRAPHICS);
      EXPECT_EQ((*pso)->push_constant_size, p.push_constant_size);
      EXPECT_EQ((*pso)->push_constant_stages, p.push_constant_stages);
      ASSERT_EQ((*pso)->set_layouts.size(), p.set_layouts.size());
      // The binding table says exactly what the archive stores, set by set.
      std::vector<format::Binding> stored;
      std::vector<uint32_t> stored_sets;
      for (uint32_t set = 0; set < p.set_layouts.size(); ++set) {
        if (p.set_layouts[set] == format::kNone) continue;
        for (const auto& b : contents.set_layouts[p.set_layouts[set]].bindings) {
          stored.push_back(b);
          stored_sets.push_back(set);
        }
      }
      ASSERT_EQ((*pso)->bindings.size(), stored.size()) << p.name;
      for (size_t i = 0; i < stored.size(); ++i)
        expect_binding((*pso)->bindings[i], stored[i], stored_sets[i], p.name);
      ++pipelines;
    }
    for (const auto& layout : contents.set_layouts) {
      if (layout.name.empty()) continue;
      auto sig = dearchiver->unpack_signature(layout.name);
      ASSERT_TRUE(sig) << sig.error().message;
      EXPECT_EQ((*sig)->set, layout.binding_index);
      ASSERT_EQ((*sig)->bindings.size(), layout.bindings.size());
      for (size_t i = 0; i < layout.bindings.size(); ++i)
        expect_binding((*sig)->bindings[i], layout.bindings[i], layout.binding_index, layout.name);
      ++signatures;
    }
    for (const auto& rp : contents.render_passes) {
      auto pass = dearchiver->unpack_render_pass(rp.name);
      ASSERT_TRUE(pass) << pass.error().message;
      ++passes;
    }
    for (uint32_t s : contents.standalone_shaders) {
      auto shader = dearchiver->unpack_shader(contents.shaders[s].name);
      ASSERT_TRUE(shader) << shader.error().message;
      EXPECT_EQ(shader->stage, static_cast<VkShaderStageFlagBits>(contents.shaders[s].stage));
      EXPECT_EQ(shader->entry_point, contents.shaders[s].entry_point);
      EXPECT_NE(shader->module, VK_NULL_HANDLE);
      ++shaders;
    }
  }
  // The corpus covers every kind of object.
  EXPECT_GT(pipelines, 5u);
  EXPECT_GT(signatures, 0u);
  EXPECT_GT(passes, 0u);
  EXPECT_GT(shaders, 0u);
  EXPECT_EQ(run_time_targets, 2u);  // run_time_render_targets.json: both pipelines need the callback
}

TEST_F(CorpusUnpack, PipelinesShareLayoutsAndSetLayouts) {
  for (const auto& path : corpus_archives()) {
    if (path.find("diligent_style") == std::string::npos) continue;
    auto archive = Archive::from_file(path);
    ASSERT_TRUE(archive);
    auto dearchiver = Dearchiver::create(vk_->device_context());
    ASSERT_TRUE(dearchiver->add_archive(std::move(*archive)));
    auto a = dearchiver->unpack_graphics("Shade PSO");
    auto b = dearchiver->unpack_graphics("Shade Again PSO");
    ASSERT_TRUE(a && b);
    EXPECT_NE((*a)->pipeline, (*b)->pipeline);
    EXPECT_EQ((*a)->layout, (*b)->layout);  // one VkPipelineLayout for equal layouts
    ASSERT_EQ((*a)->set_layouts.size(), 1u);
    EXPECT_EQ((*a)->set_layouts, (*b)->set_layouts);  // one VkDescriptorSetLayout
    const BindingInfo* sampler = (*a)->find_binding("g_Albedo_sampler");
    ASSERT_NE(sampler, nullptr);
    EXPECT_EQ(sampler->type, VK_DESCRIPTOR_TYPE_SAMPLER);
    return;
  }
  FAIL() << "no diligent_style corpus archive";
}

TEST_F(CorpusUnpack, RenderPassPipelinesRejectFormatPatches) {
  for (const auto& path : corpus_archives()) {
    if (path.find("render_pass") == std::string::npos) continue;
    auto archive = Archive::from_file(path);
    ASSERT_TRUE(archive);
    auto dearchiver = Dearchiver::create(vk_->device_context());
    ASSERT_TRUE(dearchiver->add_archive(std::move(*archive)));
    auto pso = dearchiver->unpack_graphics(
        "Depth Tested PSO", [](PatchableState& s) { s.color_formats[0] = VK_FORMAT_B8G8R8A8_UNORM; });
    ASSERT_FALSE(pso);
    EXPECT_EQ(pso.error().code, ErrorCode::invalid_argument);
    EXPECT_NE(pso.error().message.find("render pass"), std::string::npos) << pso.error().message;
    auto unknown = dearchiver->unpack_render_pass("Main Pas");
    ASSERT_FALSE(unknown);
    EXPECT_NE(unknown.error().message.find("did you mean 'Main Pass'"), std::string::npos)
        << unknown.error().message;
    return;
  }
  FAIL() << "no render_pass corpus archive";
}

}  // namespace
}  // namespace statepack::testing
