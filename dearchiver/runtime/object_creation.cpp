// The Vulkan objects the object cache makes, each once per distinct one: set layouts, samplers and render
// passes, checked against the device first. Apart from the cache's lookups (object_cache.cpp) because
// they run once per object, not per pipeline: compiled for size (dearchiver/CMakeLists.txt).
#include <deque>
#include <string>
#include <vector>

#include "object_cache.hpp"
#include "support/failure.hpp"
#include "vk_result_string.hpp"

namespace statepack::detail {

Result<VkDescriptorSetLayout> ObjectCache::create_set_layout(size_t archive, uint32_t index,
                                                             std::string_view pipeline) {
  const format::SetLayout& stored = contents(archive).set_layouts[index];
  const std::string owner = stored.name.empty() ? "a set layout of pipeline '" + std::string(pipeline) + "'"
                                                : "resource signature '" + stored.name + "'";
  if (auto ok = check_set_layout(stored, caps_, owner); !ok) return ok.error();
  std::vector<VkDescriptorSetLayoutBinding> bindings;
  bindings.reserve(stored.bindings.size());
  // One sampler array per binding with an immutable sampler, alive until the layout is created;
  // reserved, so that the pointers into it stay good.
  std::vector<std::vector<VkSampler>> immutable;
  for (const auto& b : stored.bindings) {
    const VkSampler* samplers_of_binding = nullptr;
    if (b.immutable_sampler != format::kNone) {
      // One sampler object per distinct archived sampler, shared by every layout that uses it; every
      // array element of the binding gets it (the layout owns no sampler: we destroy them last).
      auto made = sampler(archive, b.immutable_sampler, b.name);
      if (!made) return made.error();
      if (immutable.empty()) immutable.reserve(stored.bindings.size());
      samplers_of_binding = immutable.emplace_back(b.count, *made).data();
    }
    bindings.push_back({b.binding, static_cast<VkDescriptorType>(b.descriptor_type), b.count, b.stage_flags,
                        samplers_of_binding});
  }
  VkDescriptorSetLayoutCreateInfo info{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
  info.bindingCount = static_cast<uint32_t>(bindings.size());
  info.pBindings = bindings.data();
  VkDescriptorSetLayout layout = VK_NULL_HANDLE;
  if (VkResult r = caps_.vk.vkCreateDescriptorSetLayout(context_.device, &info, context_.allocator, &layout);
      r != VK_SUCCESS)
    return vulkan_failure("vkCreateDescriptorSetLayout", r, pipeline);
  return layout;
}

Result<VkSampler> ObjectCache::create_sampler(size_t archive, uint32_t index, std::string_view binding) {
  const format::Sampler& s = contents(archive).samplers[index];
  if (auto ok = check_sampler(s, caps_, binding); !ok) return ok.error();
  if (s.anisotropy_enable && !enabled_.core().samplerAnisotropy)
    return detail::failure(ErrorCode::unsupported,
                           "immutable sampler of '" + std::string(binding) +
                               "' uses anisotropic filtering, which the device does not support");
  VkSamplerCreateInfo info{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
  info.magFilter = static_cast<VkFilter>(s.mag_filter);
  info.minFilter = static_cast<VkFilter>(s.min_filter);
  info.mipmapMode = static_cast<VkSamplerMipmapMode>(s.mipmap_mode);
  info.addressModeU = static_cast<VkSamplerAddressMode>(s.address_u);
  info.addressModeV = static_cast<VkSamplerAddressMode>(s.address_v);
  info.addressModeW = static_cast<VkSamplerAddressMode>(s.address_w);
  info.mipLodBias = s.mip_lod_bias;
  info.anisotropyEnable = s.anisotropy_enable != 0;  // VkBool32 must be exactly 0 or 1
  info.maxAnisotropy = s.max_anisotropy;
  info.compareEnable = s.compare_enable != 0;
  info.compareOp = static_cast<VkCompareOp>(s.compare_op);
  info.minLod = s.min_lod;
  info.maxLod = s.max_lod;
  info.borderColor = static_cast<VkBorderColor>(s.border_color);
  info.unnormalizedCoordinates = s.unnormalized_coordinates != 0;
  VkSampler sampler = VK_NULL_HANDLE;
  if (VkResult r = caps_.vk.vkCreateSampler(context_.device, &info, context_.allocator, &sampler);
      r != VK_SUCCESS)
    return vulkan_failure("vkCreateSampler", r, binding);
  return sampler;
}

Result<VkRenderPass> ObjectCache::create_render_pass(size_t archive, uint32_t index) {
  const format::RenderPass& rp = contents(archive).render_passes[index];
  if (auto ok = check_render_pass(rp, caps_, enabled_.core()); !ok) return ok.error();
  std::vector<VkAttachmentDescription> attachments;
  for (const auto& a : rp.attachments)
    attachments.push_back(
        {0, static_cast<VkFormat>(a.format), static_cast<VkSampleCountFlagBits>(a.samples),
         static_cast<VkAttachmentLoadOp>(a.load_op), static_cast<VkAttachmentStoreOp>(a.store_op),
         static_cast<VkAttachmentLoadOp>(a.stencil_load_op),
         static_cast<VkAttachmentStoreOp>(a.stencil_store_op), static_cast<VkImageLayout>(a.initial_layout),
         static_cast<VkImageLayout>(a.final_layout)});
  auto refs = [](const std::vector<format::AttachmentRef>& list) {
    std::vector<VkAttachmentReference> out;
    for (const auto& r : list) out.push_back({r.attachment, static_cast<VkImageLayout>(r.layout)});
    return out;
  };
  std::deque<std::vector<VkAttachmentReference>> ref_storage;
  std::deque<VkAttachmentReference> depth_storage;
  std::vector<VkSubpassDescription> subpasses;
  for (const auto& sp : rp.subpasses) {
    VkSubpassDescription d{};
    d.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;
    const auto& inputs = ref_storage.emplace_back(refs(sp.inputs));
    const auto& colors = ref_storage.emplace_back(refs(sp.colors));
    const auto& resolves = ref_storage.emplace_back(refs(sp.resolves));
    d.inputAttachmentCount = static_cast<uint32_t>(inputs.size());
    d.pInputAttachments = inputs.data();
    d.colorAttachmentCount = static_cast<uint32_t>(colors.size());
    d.pColorAttachments = colors.data();
    d.pResolveAttachments = resolves.empty() ? nullptr : resolves.data();
    if (sp.depth_stencil.attachment != format::kNone)
      d.pDepthStencilAttachment = &depth_storage.emplace_back(VkAttachmentReference{
          sp.depth_stencil.attachment, static_cast<VkImageLayout>(sp.depth_stencil.layout)});
    d.preserveAttachmentCount = static_cast<uint32_t>(sp.preserve.size());
    d.pPreserveAttachments = sp.preserve.data();
    subpasses.push_back(d);
  }
  std::vector<VkSubpassDependency> dependencies;
  for (const auto& d : rp.dependencies)
    dependencies.push_back(
        {d.src_subpass, d.dst_subpass, d.src_stages, d.dst_stages, d.src_access, d.dst_access, d.flags});
  VkRenderPassCreateInfo info{VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO};
  info.attachmentCount = static_cast<uint32_t>(attachments.size());
  info.pAttachments = attachments.data();
  info.subpassCount = static_cast<uint32_t>(subpasses.size());
  info.pSubpasses = subpasses.data();
  info.dependencyCount = static_cast<uint32_t>(dependencies.size());
  info.pDependencies = dependencies.data();
  VkRenderPass pass = VK_NULL_HANDLE;
  if (VkResult r = caps_.vk.vkCreateRenderPass(context_.device, &info, context_.allocator, &pass);
      r != VK_SUCCESS)
    return vulkan_failure("vkCreateRenderPass", r, rp.name);
  return pass;
}

}  // namespace statepack::detail
