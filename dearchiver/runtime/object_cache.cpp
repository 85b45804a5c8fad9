#include "object_cache.hpp"

#include "support/failure.hpp"

#include <deque>

#include "archive_access.hpp"
#include "vk_result_string.hpp"

namespace statepack::detail {

ObjectCache::~ObjectCache() {
  VkDevice device = context_.device;
  const VkAllocationCallbacks* alloc = context_.allocator;
  for (auto& [key, layout] : pipeline_layouts_) caps_.vk.vkDestroyPipelineLayout(device, layout, alloc);
  for (auto& [key, layout] : set_layouts_by_content_)
    caps_.vk.vkDestroyDescriptorSetLayout(device, layout, alloc);
  for (auto& [key, sampler] : samplers_by_content_)
    caps_.vk.vkDestroySampler(device, sampler, alloc);  // after their layouts
  for (auto& [key, pass] : render_passes_by_content_) caps_.vk.vkDestroyRenderPass(device, pass, alloc);
  if (empty_set_layout_) caps_.vk.vkDestroyDescriptorSetLayout(device, empty_set_layout_, alloc);
  // A handed-out module may have left modules_ (its archive forgotten): destroyed from handed_out_.
  for (auto& [key, module] : modules_)
    if (!handed_out_.count(module)) caps_.vk.vkDestroyShaderModule(device, module, alloc);
  for (VkShaderModule module : handed_out_) caps_.vk.vkDestroyShaderModule(device, module, alloc);
}

void ObjectCache::forget(size_t archive) {
  auto erase_archive = [&](auto& by_index, auto&& on_erase) {
    for (auto it = by_index.lower_bound(Key{archive, 0});
         it != by_index.end() && it->first.first == archive;) {
      on_erase(it->second);
      it = by_index.erase(it);
    }
  };
  erase_archive(modules_, [&](VkShaderModule module) {
    if (!handed_out_.count(module))
      caps_.vk.vkDestroyShaderModule(context_.device, module, context_.allocator);
  });
  auto keep = [](auto) {};  // owned by content
  erase_archive(set_layouts_, keep);
  erase_archive(samplers_, keep);
  erase_archive(render_passes_, keep);
}

template <class Handle, class Create>
Result<Handle> ObjectCache::find_or_create(std::map<Key, Handle>& by_index,
                                           std::map<std::string, Handle>& by_content, Key key,
                                           const std::string& content, Create&& create) {
  if (auto it = by_index.find(key); it != by_index.end()) return it->second;
  if (auto it = by_content.find(content); it != by_content.end()) {
    by_index.emplace(key, it->second);
    return it->second;
  }
  Result<Handle> made = create();
  if (!made) return made;
  by_content.emplace(content, *made);  // owned from here on, even if the line below throws
  by_index.emplace(key, *made);
  return made;
}

// What Vulkan sees of a set layout: bindings, types, counts, stages and the immutable samplers' values
// (not the names, and not the samplers' places in an archive, which differ between archives).
std::string ObjectCache::set_layout_content(size_t archive, const format::SetLayout& layout) const {
  std::string key;
  auto put = [&](uint32_t v) { key.append(reinterpret_cast<const char*>(&v), sizeof v); };
  for (const auto& b : layout.bindings) {
    for (uint32_t v : {b.binding, b.descriptor_type, b.count, b.stage_flags}) put(v);
    const bool fixed = b.immutable_sampler != format::kNone;
    put(fixed ? 1 : 0);
    if (fixed) key += format::record_key(contents(archive).samplers[b.immutable_sampler]);
  }
  return key;
}

const format::Contents& ObjectCache::contents(size_t archive) const {
  return detail::ArchiveAccess::contents(archives_[archive]);
}

template <class Handle, class Create>
Result<Handle> ObjectCache::find_or_create(std::map<Key, Handle>& cache, Key key, Create&& create) {
  if (auto it = cache.find(key); it != cache.end()) return it->second;
  Result<Handle> made = create();
  if (made) cache.emplace(key, *made);
  return made;
}

Result<VkShaderModule> ObjectCache::module(size_t archive, uint32_t blob, std::string_view owner) {
  return find_or_create(modules_, {archive, blob}, [&]() -> Result<VkShaderModule> {
    auto words = contents(archive).spirv[blob];
    if (const spirv::Module* declared = walked(archive, blob))
      if (std::string why = enabled_.check_capabilities(declared->capabilities); !why.empty())
        return detail::failure(ErrorCode::unsupported, "shader '" + std::string(owner) + "' " + why);
    VkShaderModuleCreateInfo info{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
    info.codeSize = words.size_bytes();
    info.pCode = words.data();  // straight from the archive bytes: no copy
    VkShaderModule module = VK_NULL_HANDLE;
    if (VkResult r = caps_.vk.vkCreateShaderModule(context_.device, &info, context_.allocator, &module);
        r != VK_SUCCESS)
      return vulkan_failure("vkCreateShaderModule", r, owner);
    return module;
  });
}

Result<VkDescriptorSetLayout> ObjectCache::set_layout(size_t archive, uint32_t index,
                                                      std::string_view pipeline) {
  if (index == format::kNone) {
    if (!empty_set_layout_) {
      VkDescriptorSetLayoutCreateInfo info{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
      if (VkResult r = caps_.vk.vkCreateDescriptorSetLayout(context_.device, &info, context_.allocator,
                                                            &empty_set_layout_);
          r != VK_SUCCESS)
        return vulkan_failure("vkCreateDescriptorSetLayout", r, pipeline);
    }
    return empty_set_layout_;
  }
  if (auto it = set_layouts_.find({archive, index}); it != set_layouts_.end()) return it->second;
  // The immutable samplers first, by content as well: a layout found by content (made for another
  // archive) still has this archive's samplers known, for immutable_sampler_of.
  for (const auto& b : contents(archive).set_layouts[index].bindings)
    if (b.immutable_sampler != format::kNone)
      if (auto made = sampler(archive, b.immutable_sampler, b.name); !made) return made.error();
  const std::string content = set_layout_content(archive, contents(archive).set_layouts[index]);
  return find_or_create(set_layouts_, set_layouts_by_content_, {archive, index}, content,
                        [&] { return create_set_layout(archive, index, pipeline); });
}

Result<VkSampler> ObjectCache::sampler(size_t archive, uint32_t index, std::string_view binding) {
  if (auto it = samplers_.find({archive, index}); it != samplers_.end()) return it->second;
  return find_or_create(samplers_, samplers_by_content_, {archive, index},
                        format::record_key(contents(archive).samplers[index]),
                        [&] { return create_sampler(archive, index, binding); });
}

VkSampler ObjectCache::immutable_sampler_of(size_t archive, const format::Binding& b) const {
  if (b.immutable_sampler == format::kNone) return VK_NULL_HANDLE;
  auto it = samplers_.find(Key{archive, b.immutable_sampler});
  return it == samplers_.end() ? VK_NULL_HANDLE : it->second;
}

Result<VkRenderPass> ObjectCache::render_pass(size_t archive, uint32_t index) {
  if (auto it = render_passes_.find({archive, index}); it != render_passes_.end()) return it->second;
  return find_or_create(render_passes_, render_passes_by_content_, {archive, index},
                        format::record_key(contents(archive).render_passes[index]),
                        [&] { return create_render_pass(archive, index); });
}

Result<VkPipelineLayout> ObjectCache::pipeline_layout(const std::vector<VkDescriptorSetLayout>& set_layouts,
                                                      uint32_t push_constant_size,
                                                      uint32_t push_constant_stages,
                                                      std::string_view pipeline) {
  // Looked up by reference (the map's comparator is transparent): most pipelines share a layout, and
  // only a new one copies the list.
  if (auto it = pipeline_layouts_.find(std::tie(set_layouts, push_constant_size, push_constant_stages));
      it != pipeline_layouts_.end())
    return it->second;
  VkPushConstantRange range{push_constant_stages, 0, push_constant_size};
  VkPipelineLayoutCreateInfo info{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
  info.setLayoutCount = static_cast<uint32_t>(set_layouts.size());
  info.pSetLayouts = set_layouts.data();
  info.pushConstantRangeCount = push_constant_size > 0 ? 1 : 0;
  info.pPushConstantRanges = &range;
  VkPipelineLayout layout = VK_NULL_HANDLE;
  if (VkResult r = caps_.vk.vkCreatePipelineLayout(context_.device, &info, context_.allocator, &layout);
      r != VK_SUCCESS)
    return vulkan_failure("vkCreatePipelineLayout", r, pipeline);
  pipeline_layouts_.emplace(std::tuple{set_layouts, push_constant_size, push_constant_stages}, layout);
  return layout;
}

const spirv::Module* ObjectCache::walked(size_t archive, uint32_t blob) {
  return ArchiveAccess::walked(archives_[archive], blob);  // walked once, by the load's checks
}

// What a lookup that finds nothing makes: set layouts, samplers and render passes, checked against the
// device first.

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
