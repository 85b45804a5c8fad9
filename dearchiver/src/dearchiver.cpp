// Dearchiver: turns archived pipelines into Vulkan objects, sharing modules and set layouts.
#include "statepack/dearchiver.hpp"

#include <algorithm>
#include <array>
#include <cstring>
#include <deque>
#include <exception>
#include <map>
#include <mutex>
#include <new>
#include <optional>
#include <set>
#include <tuple>
#include <unordered_map>

#include "api_guard.hpp"
#include "archive_format.hpp"
#include "device_limits.hpp"
#include "parallel_for.hpp"
#include "patched_state_check.hpp"
#include "spirv_walk.hpp"
#include "suggest.hpp"
#include "vk_result_string.hpp"

namespace statepack {

const BindingInfo* UnpackedPipeline::find_binding(std::string_view resource_name) const {
  for (const auto& b : bindings)
    if (b.name == resource_name) return &b;
  return nullptr;
}

namespace {

Error vulkan_failure(const char* call, VkResult result, std::string_view object) {
  return Error{ErrorCode::vulkan_error,
               std::string(call) + " failed for '" + std::string(object) + "': " + vk_result_string(result)};
}

bool has_stencil(VkFormat format) {
  return format == VK_FORMAT_S8_UINT || format == VK_FORMAT_D16_UNORM_S8_UINT ||
         format == VK_FORMAT_D24_UNORM_S8_UINT || format == VK_FORMAT_D32_SFLOAT_S8_UINT;
}
bool has_depth(VkFormat format) {
  return format != VK_FORMAT_UNDEFINED && format != VK_FORMAT_S8_UINT;
}

// Dynamic states: the archive's bit mask <-> VkDynamicState (archive_format.hpp has the numbering).
std::optional<uint32_t> dynamic_state_bit(VkDynamicState state) {
  if (state >= VK_DYNAMIC_STATE_VIEWPORT && state <= VK_DYNAMIC_STATE_STENCIL_REFERENCE) return 1u << state;
  if (state >= VK_DYNAMIC_STATE_CULL_MODE && state <= VK_DYNAMIC_STATE_STENCIL_OP) {
    const uint32_t bit = 1u << (format::kDynamicExtendedFirstBit + (state - VK_DYNAMIC_STATE_CULL_MODE));
    if (bit & format::kDynamicExtendedMask) return bit;
  }
  return std::nullopt;
}
VkDynamicState dynamic_state_of_bit(uint32_t index) {
  return index < format::kDynamicExtendedFirstBit
             ? VkDynamicState(index)
             : VkDynamicState(VK_DYNAMIC_STATE_CULL_MODE + (index - format::kDynamicExtendedFirstBit));
}
std::string dynamic_state_name(VkDynamicState state) {
  static constexpr const char* kCore[] = {
      "VIEWPORT",         "SCISSOR",      "LINE_WIDTH",           "DEPTH_BIAS",
      "BLEND_CONSTANTS",  "DEPTH_BOUNDS", "STENCIL_COMPARE_MASK", "STENCIL_WRITE_MASK",
      "STENCIL_REFERENCE"};
  static constexpr const char* kExtended[] = {"CULL_MODE",           "FRONT_FACE",
                                              "PRIMITIVE_TOPOLOGY",  "VIEWPORT_WITH_COUNT",
                                              "SCISSOR_WITH_COUNT",  "VERTEX_INPUT_BINDING_STRIDE",
                                              "DEPTH_TEST_ENABLE",   "DEPTH_WRITE_ENABLE",
                                              "DEPTH_COMPARE_OP",    "DEPTH_BOUNDS_TEST_ENABLE",
                                              "STENCIL_TEST_ENABLE", "STENCIL_OP"};
  if (state >= 0 && size_t(state) < std::size(kCore)) return kCore[state];
  if (state >= VK_DYNAMIC_STATE_CULL_MODE && state <= VK_DYNAMIC_STATE_STENCIL_OP)
    return kExtended[state - VK_DYNAMIC_STATE_CULL_MODE];
  return std::to_string(int64_t(state));
}

// What the callback sees of a pipeline's constants: one entry per name, stages merged.
std::vector<SpecializationConstant> constants_of(const format::Pipeline& p) {
  std::vector<SpecializationConstant> out;
  std::unordered_map<std::string_view, size_t> index;  // name -> entry of `out`: linear, not quadratic
  for (const auto& s : p.constants) {
    if (auto it = index.find(s.name); it != index.end()) {
      out[it->second].stages |= s.stage;
      continue;
    }
    index.emplace(s.name, out.size());
    SpecializationConstant c;
    c.name = s.name;
    c.stages = s.stage;
    c.size = s.size;
    for (uint32_t i = 0; i < 8; ++i) c.value[i] = uint8_t(s.value >> (8 * i));
    out.push_back(std::move(c));
  }
  return out;
}

PatchableState to_patchable(const format::Pipeline& p) {
  PatchableState s;
  for (uint32_t i = 0; i < 32; ++i)
    if (p.dynamic_states & (1u << i)) s.dynamic_states.push_back(dynamic_state_of_bit(i));
  s.constants = constants_of(p);
  if (p.kind != format::PipelineKind::graphics) return s;
  const format::GraphicsState& g = p.graphics;
  s.color_count = g.color_count;
  for (size_t i = 0; i < s.color_formats.size(); ++i) {
    s.color_formats[i] = static_cast<VkFormat>(g.color_formats[i]);
    const auto& b = g.blend[i];
    s.blend[i] = {b.enable != 0,
                  static_cast<VkBlendFactor>(b.src_color),
                  static_cast<VkBlendFactor>(b.dst_color),
                  static_cast<VkBlendOp>(b.color_op),
                  static_cast<VkBlendFactor>(b.src_alpha),
                  static_cast<VkBlendFactor>(b.dst_alpha),
                  static_cast<VkBlendOp>(b.alpha_op),
                  b.write_mask};
  }
  s.depth_stencil_format = static_cast<VkFormat>(g.depth_stencil_format);
  s.samples = static_cast<VkSampleCountFlagBits>(g.samples);
  s.rasterizer = {static_cast<VkPolygonMode>(g.polygon_mode),
                  g.cull_mode,
                  static_cast<VkFrontFace>(g.front_face),
                  g.depth_clamp != 0,
                  g.depth_bias,
                  g.depth_bias_clamp,
                  g.depth_bias_slope};
  auto stencil = [&](const format::StencilOpState& o) {
    return VkStencilOpState{static_cast<VkStencilOp>(o.fail_op),
                            static_cast<VkStencilOp>(o.pass_op),
                            static_cast<VkStencilOp>(o.depth_fail_op),
                            static_cast<VkCompareOp>(o.compare_op),
                            g.stencil_read_mask,
                            g.stencil_write_mask,
                            0};
  };
  s.depth_stencil = {g.depth_test != 0,   g.depth_write != 0, static_cast<VkCompareOp>(g.depth_compare),
                     g.stencil_test != 0, stencil(g.front),   stencil(g.back)};
  return s;
}

}  // namespace

struct Dearchiver::State {
  DeviceContext context;
  DeviceCaps caps;                      // limits and formats, checked before any vkCreate*
  VkPhysicalDeviceFeatures features{};  // enabled (as the caller says) or supported ones
  std::vector<Archive> archives;
  std::map<std::pair<size_t, uint32_t>, VkShaderModule> modules;             // (archive, blob)
  std::map<std::pair<size_t, uint32_t>, VkDescriptorSetLayout> set_layouts;  // (archive, layout)
  std::map<std::pair<size_t, uint32_t>, VkSampler> samplers;                 // (archive, sampler)
  std::map<std::pair<size_t, uint32_t>, VkRenderPass> render_passes;         // (archive, render pass)
  std::deque<UnpackedSignature> signatures;
  std::map<std::pair<size_t, uint32_t>, const UnpackedSignature*> signature_by_layout;
  VkDescriptorSetLayout empty_set_layout = VK_NULL_HANDLE;  // fills holes in the set numbering
  // (set layouts, push constant size, push constant stages) -> layout
  std::map<std::tuple<std::vector<VkDescriptorSetLayout>, uint32_t, uint32_t>, VkPipelineLayout>
      pipeline_layouts;
  std::deque<UnpackedPipeline> pipelines;                                              // stable addresses
  std::map<std::string, const UnpackedPipeline*, std::less<>> unmodified;              // cache by name
  std::map<std::pair<size_t, uint32_t>, std::optional<spirv::Module>> walked_modules;  // (archive, blob)
  std::mutex mutex;

  ~State() {
    VkDevice device = context.device;
    const VkAllocationCallbacks* alloc = context.allocator;
    for (auto& p : pipelines) vkDestroyPipeline(device, p.pipeline, alloc);
    for (auto& [key, layout] : pipeline_layouts) vkDestroyPipelineLayout(device, layout, alloc);
    for (auto& [key, layout] : set_layouts) vkDestroyDescriptorSetLayout(device, layout, alloc);
    for (auto& [key, sampler] : samplers) vkDestroySampler(device, sampler, alloc);
    for (auto& [key, pass] : render_passes) vkDestroyRenderPass(device, pass, alloc);
    if (empty_set_layout) vkDestroyDescriptorSetLayout(device, empty_set_layout, alloc);
    for (auto& [key, module] : modules) vkDestroyShaderModule(device, module, alloc);
  }

  struct Found {
    size_t archive;
    const format::Pipeline* pipeline;
  };

  // Names of the given kinds across every archive, for listings and "did you mean".
  std::vector<std::string> names_of(std::initializer_list<ObjectKind> kinds) const {
    std::vector<std::string> names;
    for (const auto& a : archives)
      for (const auto& [name, kind] : a.objects())
        if (std::find(kinds.begin(), kinds.end(), kind) != kinds.end()) names.push_back(name);
    return names;
  }
  std::vector<std::string> all_names() const {
    return names_of({ObjectKind::graphics_pipeline, ObjectKind::compute_pipeline});
  }

  Result<Found> find(std::string_view name, format::PipelineKind kind) const {
    for (size_t i = 0; i < archives.size(); ++i) {
      const auto& list = archives[i].contents().pipelines;  // sorted by name (checked on load)
      auto it = std::lower_bound(list.begin(), list.end(), name,
                                 [](const format::Pipeline& p, std::string_view n) { return p.name < n; });
      if (it == list.end() || it->name != name) continue;
      if (it->kind != kind) {
        const char* actual = it->kind == format::PipelineKind::compute ? "compute" : "graphics";
        const char* wanted = kind == format::PipelineKind::compute ? "compute" : "graphics";
        return Error{ErrorCode::wrong_type, "pipeline '" + std::string(name) + "' is a " + actual +
                                                " pipeline, not a " + wanted + " pipeline"};
      }
      return Found{i, &*it};
    }
    auto names = all_names();
    return Error{ErrorCode::not_found, "no pipeline named '" + std::string(name) + "' in " +
                                           std::to_string(archives.size()) + " loaded archive(s)" +
                                           did_you_mean(name, names)};
  }

  // A blob's declarations, walked once (the walk succeeded at load; nullptr if it somehow does not).
  const spirv::Module* walked(size_t archive, uint32_t blob) {
    auto [it, inserted] = walked_modules.try_emplace({archive, blob});
    if (inserted)
      if (auto module = spirv::walk(archives[archive].contents().spirv[blob]))
        it->second = std::move(module.value());
    return it->second ? &*it->second : nullptr;
  }

  Result<VkShaderModule> module(size_t archive, uint32_t blob, const std::string& shader_name) {
    auto key = std::pair{archive, blob};
    if (auto it = modules.find(key); it != modules.end()) return it->second;
    auto words = archives[archive].contents().spirv[blob];
    VkShaderModuleCreateInfo info{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
    info.codeSize = words.size_bytes();
    info.pCode = words.data();  // straight from the archive bytes: no copy
    VkShaderModule module = VK_NULL_HANDLE;
    if (VkResult r = vkCreateShaderModule(context.device, &info, context.allocator, &module); r != VK_SUCCESS)
      return vulkan_failure("vkCreateShaderModule", r, shader_name);
    modules.emplace(key, module);
    return module;
  }

  Result<VkDescriptorSetLayout> set_layout(size_t archive, uint32_t index, std::string_view pipeline) {
    if (index == format::kNone) {
      if (!empty_set_layout) {
        VkDescriptorSetLayoutCreateInfo info{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
        if (VkResult r =
                vkCreateDescriptorSetLayout(context.device, &info, context.allocator, &empty_set_layout);
            r != VK_SUCCESS)
          return vulkan_failure("vkCreateDescriptorSetLayout", r, pipeline);
      }
      return empty_set_layout;
    }
    auto key = std::pair{archive, index};
    if (auto it = set_layouts.find(key); it != set_layouts.end()) return it->second;
    const auto& stored = archives[archive].contents().set_layouts[index];
    const std::string owner = stored.name.empty() ? "a set layout of pipeline '" + std::string(pipeline) + "'"
                                                  : "resource signature '" + stored.name + "'";
    if (auto ok = check_set_layout(stored, caps, owner); !ok) return ok.error();
    std::vector<VkDescriptorSetLayoutBinding> bindings;
    std::deque<std::vector<VkSampler>> immutable;  // alive until the layout is created
    for (const auto& b : stored.bindings) {
      const VkSampler* samplers_of_binding = nullptr;
      if (b.immutable_sampler != format::kNone) {
        // One sampler object per distinct archived sampler, shared by every layout that uses it; every
        // array element of the binding gets it (the layout owns no sampler: we destroy them last).
        auto made = sampler(archive, b.immutable_sampler, b.name);
        if (!made) return made.error();
        samplers_of_binding = immutable.emplace_back(b.count, *made).data();
      }
      bindings.push_back({b.binding, static_cast<VkDescriptorType>(b.descriptor_type), b.count, b.stage_flags,
                          samplers_of_binding});
    }
    VkDescriptorSetLayoutCreateInfo info{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
    info.bindingCount = static_cast<uint32_t>(bindings.size());
    info.pBindings = bindings.data();
    VkDescriptorSetLayout layout = VK_NULL_HANDLE;
    if (VkResult r = vkCreateDescriptorSetLayout(context.device, &info, context.allocator, &layout);
        r != VK_SUCCESS)
      return vulkan_failure("vkCreateDescriptorSetLayout", r, pipeline);
    set_layouts.emplace(key, layout);
    return layout;
  }

  Result<VkSampler> sampler(size_t archive, uint32_t index, std::string_view binding) {
    auto key = std::pair{archive, index};
    if (auto it = samplers.find(key); it != samplers.end()) return it->second;
    const format::Sampler& s = archives[archive].contents().samplers[index];
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
    if (auto ok = check_sampler(s, caps, binding); !ok) return ok.error();
    if (s.anisotropy_enable) {
      if (!features.samplerAnisotropy)
        return Error{ErrorCode::unsupported,
                     "immutable sampler of '" + std::string(binding) +
                         "' uses anisotropic filtering, which the device does not support"};
    }
    VkSampler sampler = VK_NULL_HANDLE;
    if (VkResult r = vkCreateSampler(context.device, &info, context.allocator, &sampler); r != VK_SUCCESS)
      return vulkan_failure("vkCreateSampler", r, binding);
    samplers.emplace(key, sampler);
    return sampler;
  }

  // The sampler object created for a binding's immutable sampler (set_layout made it), or null.
  VkSampler immutable_sampler_of(size_t archive, const format::Binding& b) const {
    if (b.immutable_sampler == format::kNone) return VK_NULL_HANDLE;
    auto it = samplers.find(std::pair{archive, b.immutable_sampler});
    return it == samplers.end() ? VK_NULL_HANDLE : it->second;
  }

  Result<VkRenderPass> render_pass(size_t archive, uint32_t index) {
    auto key = std::pair{archive, index};
    if (auto it = render_passes.find(key); it != render_passes.end()) return it->second;
    const format::RenderPass& rp = archives[archive].contents().render_passes[index];
    if (auto ok = check_render_pass(rp, caps, features); !ok) return ok.error();
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
    if (VkResult r = vkCreateRenderPass(context.device, &info, context.allocator, &pass); r != VK_SUCCESS)
      return vulkan_failure("vkCreateRenderPass", r, rp.name);
    render_passes.emplace(key, pass);
    return pass;
  }

  // The first archive that has an object of that name; `names` lists them all for suggestions.
  template <class Find>
  std::optional<std::pair<size_t, uint32_t>> find_named(Find&& find_in) const {
    for (size_t i = 0; i < archives.size(); ++i)
      if (auto index = find_in(archives[i].contents())) return std::pair{i, *index};
    return std::nullopt;
  }

  // A pipeline ready to create: every shared object exists and every create-info field is filled.
  // Heap-allocated so the pointers between the structs stay valid.
  struct Plan {
    UnpackedPipeline out;
    bool cacheable = true;
    std::vector<VkPipelineShaderStageCreateInfo> stages;
    VkComputePipelineCreateInfo compute{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
    PatchableState state;
    std::vector<VkVertexInputBindingDescription> vertex_bindings;
    std::vector<VkVertexInputAttributeDescription> vertex_attributes;
    VkPipelineVertexInputStateCreateInfo vertex_input{
        VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO};
    VkPipelineInputAssemblyStateCreateInfo assembly{
        VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO};
    VkPipelineTessellationStateCreateInfo tessellation{
        VK_STRUCTURE_TYPE_PIPELINE_TESSELLATION_STATE_CREATE_INFO};
    VkPipelineViewportStateCreateInfo viewport{VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO};
    VkPipelineRasterizationStateCreateInfo raster{VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO};
    VkPipelineMultisampleStateCreateInfo multisample{
        VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO};
    VkSampleMask sample_mask = 0xFFFFFFFFu;
    VkPipelineDepthStencilStateCreateInfo depth{VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO};
    std::array<VkPipelineColorBlendAttachmentState, 8> attachments{};
    VkPipelineColorBlendStateCreateInfo blend{VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO};
    std::vector<VkDynamicState> dynamic_states;
    struct StageConstants {
      std::vector<VkSpecializationMapEntry> entries;
      std::vector<uint8_t> data;
      VkSpecializationInfo info{};
    };
    std::vector<StageConstants> constants;  // one per stage, sized before pointers into it are taken
    VkPipelineDynamicStateCreateInfo dynamic{VK_STRUCTURE_TYPE_PIPELINE_DYNAMIC_STATE_CREATE_INFO};
    VkPipelineRenderingCreateInfo rendering{VK_STRUCTURE_TYPE_PIPELINE_RENDERING_CREATE_INFO};
    VkGraphicsPipelineCreateInfo graphics{VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO};
  };

  // Layout, set layouts, binding table and shader stages: what both kinds of pipeline need.
  // The constants a callback settled, checked against the archive's: known names, unchanged sizes.
  static Result<std::vector<SpecializationConstant>> settle_constants(
      const format::Pipeline& p, std::vector<SpecializationConstant> given) {
    std::vector<SpecializationConstant> archived = constants_of(p);
    std::unordered_map<std::string_view, size_t> index;
    for (size_t i = 0; i < archived.size(); ++i) index.emplace(archived[i].name, i);
    for (const auto& g : given) {
      auto it = index.find(g.name);
      if (it == index.end())
        return Error{ErrorCode::invalid_argument, "pipeline '" + p.name +
                                                      "' has no specialization constant '" + g.name +
                                                      "' (the modify callback added it)"};
      SpecializationConstant& a = archived[it->second];
      if (g.size != a.size)
        return Error{ErrorCode::invalid_argument, "pipeline '" + p.name + "': specialization constant '" +
                                                      g.name + "' is " + std::to_string(a.size) +
                                                      " bytes, but the modify callback gave " +
                                                      std::to_string(g.size)};
      a.value = g.value;  // a constant the callback removed keeps the archived value
    }
    return archived;
  }

  Result<std::unique_ptr<Plan>> plan_common(const Found& found,
                                            const std::vector<SpecializationConstant>& constants) {
    const format::Pipeline& p = *found.pipeline;
    const auto& contents = archives[found.archive].contents();
    if (!(contents.backends & format::kBackendVulkan))
      return Error{ErrorCode::missing_backend, "pipeline '" + p.name + "': the archive has no Vulkan data"};
    if (auto ok = check_pipeline_layout(contents, p, caps); !ok) return ok.error();
    auto plan = std::make_unique<Plan>();
    UnpackedPipeline& out = plan->out;
    out.name = p.name;
    out.push_constant_size = p.push_constant_size;
    out.push_constant_stages = p.push_constant_stages;
    for (uint32_t set = 0; set < p.set_layouts.size(); ++set) {
      auto layout = set_layout(found.archive, p.set_layouts[set], p.name);
      if (!layout) return layout.error();
      out.set_layouts.push_back(*layout);
      if (p.set_layouts[set] == format::kNone) continue;
      for (const auto& b : contents.set_layouts[p.set_layouts[set]].bindings)
        out.bindings.push_back({b.name, set, b.binding, static_cast<VkDescriptorType>(b.descriptor_type),
                                b.count, b.stage_flags, immutable_sampler_of(found.archive, b)});
    }
    auto layout_key = std::tuple{out.set_layouts, p.push_constant_size, p.push_constant_stages};
    if (auto it = pipeline_layouts.find(layout_key); it != pipeline_layouts.end()) {
      out.layout = it->second;
    } else {
      VkPushConstantRange range{p.push_constant_stages, 0, p.push_constant_size};
      VkPipelineLayoutCreateInfo info{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
      info.setLayoutCount = static_cast<uint32_t>(out.set_layouts.size());
      info.pSetLayouts = out.set_layouts.data();
      info.pushConstantRangeCount = p.push_constant_size > 0 ? 1 : 0;
      info.pPushConstantRanges = &range;
      if (VkResult r = vkCreatePipelineLayout(context.device, &info, context.allocator, &out.layout);
          r != VK_SUCCESS)
        return vulkan_failure("vkCreatePipelineLayout", r, p.name);
      pipeline_layouts.emplace(std::move(layout_key), out.layout);
    }
    uint32_t stages = 0;
    plan->constants.resize(p.shaders.size());
    std::unordered_map<std::string_view, const SpecializationConstant*> value_of;
    for (const auto& v : constants) value_of.emplace(v.name, &v);
    for (uint32_t s : p.shaders) {
      const format::Shader& shader = contents.shaders[s];
      auto module = this->module(found.archive, shader.blob, shader.name);
      if (!module) return module.error();
      VkPipelineShaderStageCreateInfo stage{VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO};
      stage.stage = static_cast<VkShaderStageFlagBits>(shader.stage);
      stage.module = *module;
      stage.pName = shader.entry_point.c_str();
      // This stage's specialization constants: one map entry each, values packed one after another.
      Plan::StageConstants& sc = plan->constants[plan->stages.size()];
      for (const auto& k : p.constants) {
        if (k.stage != shader.stage) continue;
        const SpecializationConstant* v = value_of.at(k.name);
        sc.entries.push_back({k.constant_id, uint32_t(sc.data.size()), k.size});
        sc.data.insert(sc.data.end(), v->value.begin(), v->value.begin() + k.size);
      }
      if (!sc.entries.empty()) {
        sc.info = {uint32_t(sc.entries.size()), sc.entries.data(), sc.data.size(), sc.data.data()};
        stage.pSpecializationInfo = &sc.info;
      }
      plan->stages.push_back(stage);
      stages |= shader.stage;
    }
    if ((stages & VK_SHADER_STAGE_GEOMETRY_BIT) && !features.geometryShader)
      return missing_feature(p.name, "geometryShader");
    if ((stages & (VK_SHADER_STAGE_TESSELLATION_CONTROL_BIT | VK_SHADER_STAGE_TESSELLATION_EVALUATION_BIT)) &&
        !features.tessellationShader)
      return missing_feature(p.name, "tessellationShader");
    return plan;
  }

  static Error missing_feature(std::string_view pipeline, const char* feature) {
    return Error{ErrorCode::unsupported, "pipeline '" + std::string(pipeline) +
                                             "' needs the device feature '" + feature +
                                             "', which is not enabled"};
  }

  // Runs the caller's callback. What it throws becomes an error naming the pipeline, here, so that an
  // unpack_all caller learns which pipeline's patch failed; bad_alloc goes on to api_guard
  // (out_of_memory), as for the library's own allocations.
  static std::optional<Error> run_modify(const std::string& pipeline, const ModifyCallback& modify,
                                         PatchableState& state) {
    try {
      modify(state);
      return std::nullopt;
    } catch (const std::bad_alloc&) {
      throw;
    } catch (const std::exception& e) {
      return Error{ErrorCode::invalid_argument,
                   "pipeline '" + pipeline + "': the modify callback threw: " + e.what()};
    } catch (...) {
      return Error{ErrorCode::invalid_argument, "pipeline '" + pipeline + "': the modify callback threw"};
    }
  }

  Result<std::unique_ptr<Plan>> plan_compute(const Found& found, const ModifyCallback& modify) {
    PatchableState settled = to_patchable(*found.pipeline);
    if (modify)  // only the constants apply to a compute pipeline
      if (auto thrown = run_modify(found.pipeline->name, modify, settled)) return *thrown;
    auto constants = settle_constants(*found.pipeline, std::move(settled.constants));
    if (!constants) return constants.error();
    auto plan = plan_common(found, *constants);
    if (!plan) return plan.error();
    Plan& pl = **plan;
    pl.cacheable = !modify;
    pl.out.bind_point = VK_PIPELINE_BIND_POINT_COMPUTE;
    pl.compute.stage = pl.stages.at(0);
    pl.compute.layout = pl.out.layout;
    return plan;
  }

  Result<std::unique_ptr<Plan>> plan_graphics(const Found& found, const ModifyCallback& modify) {
    const format::GraphicsState& g = found.pipeline->graphics;
    const std::string& name = found.pipeline->name;
    const bool uses_render_pass = found.pipeline->render_pass != format::kNone;
    if (!uses_render_pass && !context.dynamic_rendering_enabled)
      return Error{ErrorCode::unsupported,
                   "pipeline '" + name + "' uses dynamic rendering, which the device was not created with"};
    // The state is settled and checked first, so that nothing is created for a pipeline that fails.
    PatchableState settled = to_patchable(*found.pipeline);
    if (modify) {
      const PatchableState before = settled;
      if (auto thrown = run_modify(name, modify, settled)) return *thrown;
      if (uses_render_pass &&
          (settled.color_count != before.color_count || settled.color_formats != before.color_formats ||
           settled.depth_stencil_format != before.depth_stencil_format || settled.samples != before.samples))
        return Error{ErrorCode::invalid_argument,
                     "pipeline '" + name +
                         "' uses a render pass, which fixes its attachment formats and "
                         "sample count; the modify callback may not change them"};
    }
    // Every value the callback left is checked as the archive's were at load, before any reaches Vulkan.
    if (modify)
      if (auto bad = check_patched_state(name, settled)) return *bad;
    // UNKNOWN in RTVFormats means "set at run time" (a swapchain's format): left unset, it is an error
    // rather than a pipeline silently created for VK_FORMAT_UNDEFINED.
    if (!uses_render_pass)
      for (uint32_t i = 0; i < settled.color_count; ++i)
        if (settled.color_formats[i] == VK_FORMAT_UNDEFINED)
          return Error{ErrorCode::invalid_argument,
                       "pipeline '" + name + "': render target " + std::to_string(i) +
                           " is UNKNOWN (a format set at run time); set PatchableState::color_formats[" +
                           std::to_string(i) + "] in the modify callback"};
    if (auto missing = check_features(name, settled)) return *missing;
    auto dynamic_mask = settle_dynamic_states(name, settled.dynamic_states);
    if (!dynamic_mask) return dynamic_mask.error();
    auto constants = settle_constants(*found.pipeline, settled.constants);
    if (!constants) return constants.error();
    // Adjacency topologies need the geometry shader feature; patch lists go with tessellation, only.
    if (g.topology >= VK_PRIMITIVE_TOPOLOGY_LINE_LIST_WITH_ADJACENCY &&
        g.topology <= VK_PRIMITIVE_TOPOLOGY_TRIANGLE_STRIP_WITH_ADJACENCY && !features.geometryShader)
      return missing_feature(name, "geometryShader");
    {
      bool tessellation = false;
      for (uint32_t index : found.pipeline->shaders)
        tessellation |=
            (archives[found.archive].contents().shaders[index].stage &
             (VK_SHADER_STAGE_TESSELLATION_CONTROL_BIT | VK_SHADER_STAGE_TESSELLATION_EVALUATION_BIT)) != 0;
      if (tessellation != (g.topology == VK_PRIMITIVE_TOPOLOGY_PATCH_LIST))
        return Error{ErrorCode::corrupt,
                     "pipeline '" + name + "' " +
                         (tessellation ? "tessellates without" : "draws patches without") +
                         " a patch list topology and tessellation shaders together"};
      if (g.patch_control_points > caps.properties.limits.maxTessellationPatchSize)
        return Error{ErrorCode::unsupported,
                     "pipeline '" + name + "' has patches of " + std::to_string(g.patch_control_points) +
                         " control points; the device allows " +
                         std::to_string(caps.properties.limits.maxTessellationPatchSize)};
    }
    std::array<bool, 8> blend_enabled{};
    for (size_t i = 0; i < blend_enabled.size(); ++i) blend_enabled[i] = settled.blend[i].enable;
    const GraphicsTargets targets{settled.color_count, settled.color_formats.data(),
                                  settled.depth_stencil_format, settled.samples, blend_enabled.data()};
    const auto& contents = archives[found.archive].contents();
    if (uses_render_pass)
      if (auto ok = check_render_pass(contents.render_passes[found.pipeline->render_pass], caps, features);
          !ok)
        return ok.error();
    if (auto ok = check_graphics_state(contents, *found.pipeline, targets, caps,
                                       [&](uint32_t blob) { return walked(found.archive, blob); });
        !ok)
      return ok.error();

    auto planned = plan_common(found, *constants);
    if (!planned) return planned.error();
    Plan& pl = **planned;
    pl.out.bind_point = VK_PIPELINE_BIND_POINT_GRAPHICS;
    pl.cacheable = !modify;
    pl.state = settled;
    const PatchableState& s = pl.state;
    VkRenderPass render_pass = VK_NULL_HANDLE;
    if (uses_render_pass) {
      auto pass = this->render_pass(found.archive, found.pipeline->render_pass);
      if (!pass) return pass.error();
      render_pass = *pass;
    }

    for (const auto& b : g.vertex_bindings)
      pl.vertex_bindings.push_back({b.binding, b.stride, static_cast<VkVertexInputRate>(b.input_rate)});
    // Attributes the vertex shader does not read have no effect; leaving them out keeps the layer
    // from warning about them (a re-sealed archive can add any).
    const spirv::Module* vertex_module = nullptr;
    for (uint32_t index : found.pipeline->shaders)
      if (contents.shaders[index].stage == VK_SHADER_STAGE_VERTEX_BIT)
        vertex_module = walked(found.archive, contents.shaders[index].blob);
    auto read_by_shader = [&](uint32_t location) {
      if (!vertex_module) return true;
      return std::any_of(vertex_module->inputs.begin(), vertex_module->inputs.end(),
                         [&](const spirv::Input& in) {
                           return location >= in.location && location < uint64_t(in.location) + in.locations;
                         });
    };
    for (const auto& a : g.vertex_attributes)
      if (read_by_shader(a.location))
        pl.vertex_attributes.push_back({a.location, a.binding, static_cast<VkFormat>(a.format), a.offset});
    pl.vertex_input.vertexBindingDescriptionCount = static_cast<uint32_t>(pl.vertex_bindings.size());
    pl.vertex_input.pVertexBindingDescriptions = pl.vertex_bindings.data();
    pl.vertex_input.vertexAttributeDescriptionCount = static_cast<uint32_t>(pl.vertex_attributes.size());
    pl.vertex_input.pVertexAttributeDescriptions = pl.vertex_attributes.data();
    pl.assembly.topology = static_cast<VkPrimitiveTopology>(g.topology);
    pl.tessellation.patchControlPoints = g.patch_control_points;  // 1..32 exactly when a patch list
    pl.viewport.viewportCount = 1;
    pl.viewport.scissorCount = 1;
    pl.raster.depthClampEnable = s.rasterizer.depth_clamp;
    pl.raster.polygonMode = s.rasterizer.polygon_mode;
    pl.raster.cullMode = s.rasterizer.cull_mode;
    pl.raster.frontFace = s.rasterizer.front_face;
    // With a dynamic depth bias the bias is set per draw, so biasing must be on.
    pl.raster.depthBiasEnable = s.rasterizer.depth_bias != 0 || s.rasterizer.depth_bias_slope != 0 ||
                                (*dynamic_mask & format::kDynamicDepthBias) != 0;
    pl.raster.depthBiasConstantFactor = s.rasterizer.depth_bias;
    pl.raster.depthBiasClamp = s.rasterizer.depth_bias_clamp;
    pl.raster.depthBiasSlopeFactor = s.rasterizer.depth_bias_slope;
    pl.raster.lineWidth = 1.0f;
    pl.multisample.rasterizationSamples = s.samples;
    pl.sample_mask = g.sample_mask;
    pl.multisample.pSampleMask = &pl.sample_mask;
    pl.multisample.alphaToCoverageEnable = g.alpha_to_coverage != 0;  // VkBool32: exactly 0 or 1
    const bool depth_attachment = has_depth(s.depth_stencil_format);
    const bool stencil_attachment = has_stencil(s.depth_stencil_format);
    pl.depth.depthTestEnable = depth_attachment && s.depth_stencil.depth_test;
    pl.depth.depthWriteEnable = depth_attachment && s.depth_stencil.depth_write;
    pl.depth.depthCompareOp = s.depth_stencil.depth_compare;
    pl.depth.stencilTestEnable = stencil_attachment && s.depth_stencil.stencil_test;
    pl.depth.front = s.depth_stencil.front;
    pl.depth.back = s.depth_stencil.back;
    pl.depth.maxDepthBounds = 1.0f;
    // Dynamic depth bounds are set per draw: the test is on (settle_dynamic_states checked the feature).
    pl.depth.depthBoundsTestEnable = (*dynamic_mask & format::kDynamicDepthBounds) != 0;
    for (uint32_t i = 0; i < s.color_count; ++i) {
      const auto& b = s.blend[i];
      pl.attachments[i] = {b.enable,    b.src_color, b.dst_color, b.color_op,
                           b.src_alpha, b.dst_alpha, b.alpha_op,  b.write_mask};
    }
    pl.blend.attachmentCount = s.color_count;
    pl.blend.pAttachments = pl.attachments.data();
    pl.dynamic_states = s.dynamic_states;
    pl.dynamic.dynamicStateCount = static_cast<uint32_t>(pl.dynamic_states.size());
    pl.dynamic.pDynamicStates = pl.dynamic_states.data();
    pl.rendering.colorAttachmentCount = s.color_count;
    pl.rendering.pColorAttachmentFormats = s.color_formats.data();
    pl.rendering.depthAttachmentFormat = depth_attachment ? s.depth_stencil_format : VK_FORMAT_UNDEFINED;
    pl.rendering.stencilAttachmentFormat = stencil_attachment ? s.depth_stencil_format : VK_FORMAT_UNDEFINED;

    VkGraphicsPipelineCreateInfo& info = pl.graphics;
    info.pNext = uses_render_pass ? nullptr : &pl.rendering;
    info.renderPass = render_pass;
    info.subpass = found.pipeline->subpass;
    info.stageCount = static_cast<uint32_t>(pl.stages.size());
    info.pStages = pl.stages.data();
    info.pVertexInputState = &pl.vertex_input;
    info.pInputAssemblyState = &pl.assembly;
    info.pTessellationState = g.topology == VK_PRIMITIVE_TOPOLOGY_PATCH_LIST ? &pl.tessellation : nullptr;
    info.pViewportState = &pl.viewport;
    info.pRasterizationState = &pl.raster;
    info.pMultisampleState = &pl.multisample;
    info.pDepthStencilState = &pl.depth;
    info.pColorBlendState = &pl.blend;
    info.pDynamicState = &pl.dynamic;
    info.layout = pl.out.layout;
    return planned;
  }

  // The dynamic states a callback settled: each one statepack supports and the device has, viewport and
  // scissor included, none twice. Returns them as the archive's bit mask.
  Result<uint32_t> settle_dynamic_states(const std::string& name, std::vector<VkDynamicState>& states) {
    uint32_t mask = 0;
    for (VkDynamicState state : states) {
      auto bit = dynamic_state_bit(state);
      if (!bit)
        return Error{ErrorCode::unsupported, "pipeline '" + name + "': dynamic state " +
                                                 dynamic_state_name(state) +
                                                 " is not supported by the dearchiver"};
      if ((*bit & format::kDynamicExtendedMask) && caps.properties.apiVersion < VK_API_VERSION_1_3)
        return Error{ErrorCode::unsupported,
                     "pipeline '" + name + "': dynamic state " + dynamic_state_name(state) +
                         " needs Vulkan 1.3 (extended dynamic state), which the device lacks"};
      if ((*bit & (format::kDynamicDepthBounds | (1u << 18))) && !features.depthBounds)
        return missing_feature(name, "depthBounds");
      mask |= *bit;
    }
    if ((mask & format::kDynamicLegacy) != format::kDynamicLegacy)
      return Error{ErrorCode::invalid_argument,
                   "pipeline '" + name +
                       "': viewport and scissor must stay dynamic (the modify callback removed one)"};
    // Canonical order, duplicates gone: what Vulkan gets and what the callback of the next unpack sees.
    states.clear();
    for (uint32_t i = 0; i < 32; ++i)
      if (mask & (1u << i)) states.push_back(dynamic_state_of_bit(i));
    return mask;
  }

  // The device features a graphics state needs, checked against the enabled ones.
  std::optional<Error> check_features(const std::string& name, const PatchableState& s) {
    if (s.rasterizer.depth_clamp && !features.depthClamp) return missing_feature(name, "depthClamp");
    if (s.rasterizer.polygon_mode != VK_POLYGON_MODE_FILL && !features.fillModeNonSolid)
      return missing_feature(name, "fillModeNonSolid");
    if (s.rasterizer.depth_bias_clamp != 0 && !features.depthBiasClamp)
      return missing_feature(name, "depthBiasClamp");
    for (uint32_t i = 0; i < s.color_count; ++i) {
      const auto& b = s.blend[i];
      auto dual = [](VkBlendFactor f) {
        return f >= VK_BLEND_FACTOR_SRC1_COLOR && f <= VK_BLEND_FACTOR_ONE_MINUS_SRC1_ALPHA;
      };
      // Dual-source factors need the feature even when blending is off (VUID-...-00608).
      if ((dual(b.src_color) || dual(b.dst_color) || dual(b.src_alpha) || dual(b.dst_alpha)) &&
          !features.dualSrcBlend)
        return missing_feature(name, "dualSrcBlend");
      if (i > 0 && !features.independentBlend &&
          std::memcmp(&s.blend[i], &s.blend[0], sizeof(BlendAttachmentState)) != 0)
        return missing_feature(name, "independentBlend");
    }
    VkPhysicalDeviceProperties properties;
    vkGetPhysicalDeviceProperties(context.physical_device, &properties);
    const VkSampleCountFlags counts = s.color_count > 0
                                          ? properties.limits.framebufferColorSampleCounts
                                          : properties.limits.framebufferNoAttachmentsSampleCounts;
    if (!(counts & s.samples))
      return Error{ErrorCode::unsupported, "pipeline '" + name + "' renders with " +
                                               std::to_string(s.samples) +
                                               " samples, which the device does not support"};
    return std::nullopt;
  }

  // Creates the pipeline of a plan; safe to call for different plans on several threads.
  Result<void> create(Plan& plan) const {
    VkResult r = plan.out.bind_point == VK_PIPELINE_BIND_POINT_COMPUTE
                     ? vkCreateComputePipelines(context.device, context.pipeline_cache, 1, &plan.compute,
                                                context.allocator, &plan.out.pipeline)
                     : vkCreateGraphicsPipelines(context.device, context.pipeline_cache, 1, &plan.graphics,
                                                 context.allocator, &plan.out.pipeline);
    if (r != VK_SUCCESS)
      return vulkan_failure(plan.out.bind_point == VK_PIPELINE_BIND_POINT_COMPUTE
                                ? "vkCreateComputePipelines"
                                : "vkCreateGraphicsPipelines",
                            r, plan.out.name);
    return {};
  }

  const UnpackedPipeline* keep(Plan& plan) {
    pipelines.push_back(std::move(plan.out));
    const UnpackedPipeline* kept = &pipelines.back();
    if (plan.cacheable) unmodified.emplace(kept->name, kept);
    return kept;
  }

  // Cached, or planned, created and kept.
  Result<const UnpackedPipeline*> unpack(std::string_view name, format::PipelineKind kind,
                                         const ModifyCallback& modify) {
    const VkPipelineBindPoint bind_point = kind == format::PipelineKind::compute
                                               ? VK_PIPELINE_BIND_POINT_COMPUTE
                                               : VK_PIPELINE_BIND_POINT_GRAPHICS;
    if (!modify)
      if (auto it = unmodified.find(name); it != unmodified.end() && it->second->bind_point == bind_point)
        return it->second;
    auto found = find(name, kind);
    if (!found) return found.error();
    auto plan =
        kind == format::PipelineKind::compute ? plan_compute(*found, modify) : plan_graphics(*found, modify);
    if (!plan) return plan.error();
    if (auto created = create(**plan); !created) return created.error();
    return keep(**plan);
  }
};

Dearchiver::Dearchiver(std::unique_ptr<State> state) : state_(std::move(state)) {}
Dearchiver::Dearchiver(Dearchiver&&) noexcept = default;
Dearchiver& Dearchiver::operator=(Dearchiver&&) noexcept = default;
Dearchiver::~Dearchiver() = default;

Result<Dearchiver> Dearchiver::create(const DeviceContext& context) {
  return api_guard("Dearchiver::create", [&]() -> Result<Dearchiver> {
    if (context.device == VK_NULL_HANDLE || context.physical_device == VK_NULL_HANDLE)
      return Error{ErrorCode::invalid_argument, "Dearchiver::create needs a VkPhysicalDevice and a VkDevice"};
    auto state = std::make_unique<State>();
    state->context = context;
    state->caps.physical_device = context.physical_device;
    vkGetPhysicalDeviceProperties(context.physical_device, &state->caps.properties);
    if (context.enabled_features)
      state->features = *context.enabled_features;
    else
      vkGetPhysicalDeviceFeatures(context.physical_device, &state->features);
    return Dearchiver(std::move(state));
  });
}

Result<void> Dearchiver::add_archive(Archive archive) {
  return api_guard("Dearchiver::add_archive", [&]() -> Result<void> {
    std::lock_guard lock(state_->mutex);
    state_->archives.push_back(std::move(archive));
    return {};
  });
}

std::vector<std::string> Dearchiver::pipeline_names() const {
  std::lock_guard lock(state_->mutex);
  return state_->all_names();
}

Result<const UnpackedPipeline*> Dearchiver::unpack_compute(std::string_view name,
                                                           const ModifyCallback& modify) {
  return api_guard("Dearchiver::unpack_compute", [&]() -> Result<const UnpackedPipeline*> {
    std::lock_guard lock(state_->mutex);
    return state_->unpack(name, format::PipelineKind::compute, modify);
  });
}

Result<const UnpackedPipeline*> Dearchiver::unpack_graphics(std::string_view name,
                                                            const ModifyCallback& modify) {
  return api_guard("Dearchiver::unpack_graphics", [&]() -> Result<const UnpackedPipeline*> {
    std::lock_guard lock(state_->mutex);
    return state_->unpack(name, format::PipelineKind::graphics, modify);
  });
}

Result<std::vector<const UnpackedPipeline*>> Dearchiver::unpack_all(uint32_t threads) {
  return unpack_all(PatchCallback{}, threads);
}

Result<std::vector<const UnpackedPipeline*>> Dearchiver::unpack_all(const PatchCallback& patch,
                                                                    uint32_t threads) {
  return api_guard("Dearchiver::unpack_all", [&]() -> Result<std::vector<const UnpackedPipeline*>> {
    auto pipelines = unpack_all_pipelines(threads, patch);
    if (!pipelines) return pipelines.error();
    // The other named objects too, so that everything is ready.
    std::vector<ObjectInfo> objects;
    {
      std::lock_guard lock(state_->mutex);
      for (const auto& archive : state_->archives) {
        auto more = archive.objects();
        objects.insert(objects.end(), more.begin(), more.end());
      }
    }
    for (const auto& [name, kind] : objects) {
      Result<void> ok;
      if (kind == ObjectKind::resource_signature) {
        if (auto r = unpack_signature(name); !r) ok = r.error();
      } else if (kind == ObjectKind::render_pass) {
        if (auto r = unpack_render_pass(name); !r) ok = r.error();
      } else if (kind == ObjectKind::shader) {
        if (auto r = unpack_shader(name); !r) ok = r.error();
      }
      if (!ok) return ok.error();
    }
    return pipelines;
  });
}

Result<std::vector<const UnpackedPipeline*>> Dearchiver::unpack_all_pipelines(uint32_t threads,
                                                                              const PatchCallback& patch) {
  std::lock_guard lock(state_->mutex);
  // Plan every pipeline not yet unpacked (serially: shared objects are created once), then create the
  // pipelines on `threads` threads: the driver's compile is the expensive part.
  std::vector<std::unique_ptr<State::Plan>> plans;
  std::vector<const UnpackedPipeline*> done;
  std::set<std::string, std::less<>> seen;
  for (size_t a = 0; a < state_->archives.size(); ++a) {
    for (const auto& p : state_->archives[a].contents().pipelines) {
      if (!seen.insert(p.name).second) continue;  // the earliest archive wins
      if (!patch)  // a patch callback sees every pipeline, so nothing made earlier is reused then
        if (auto it = state_->unmodified.find(p.name); it != state_->unmodified.end()) {
          done.push_back(it->second);
          continue;
        }
      State::Found found{a, &p};
      const bool compute = p.kind == format::PipelineKind::compute;
      // The single-object path's callback, told which pipeline it patches: the patched state goes
      // through the same checks as unpack_graphics/unpack_compute with a modify callback.
      ModifyCallback modify;
      if (patch) {
        const ObjectInfo object{p.name,
                                compute ? ObjectKind::compute_pipeline : ObjectKind::graphics_pipeline};
        modify = [&patch, object](PatchableState& s) { patch(object, s); };
      }
      auto plan = compute ? state_->plan_compute(found, modify) : state_->plan_graphics(found, modify);
      if (!plan) return plan.error();
      plans.push_back(std::move(plan.value()));
    }
  }
  std::vector<std::optional<Error>> failures(plans.size());
  parallel_for(plans.size(), threads, [&](size_t i) {
    if (auto created = state_->create(*plans[i]); !created) failures[i] = created.error();
  });
  std::optional<Error> first_failure;
  for (size_t i = 0; i < plans.size(); ++i) {
    if (failures[i]) {
      if (!first_failure) first_failure = failures[i];
      continue;
    }
    done.push_back(state_->keep(*plans[i]));  // kept, so destroyed with the dearchiver even on failure
  }
  if (first_failure) return *first_failure;
  return done;
}

Result<const UnpackedSignature*> Dearchiver::unpack_signature(std::string_view name) {
  return api_guard("Dearchiver::unpack_signature", [&]() -> Result<const UnpackedSignature*> {
    std::lock_guard lock(state_->mutex);
    auto found = state_->find_named([&](const format::Contents& c) -> std::optional<uint32_t> {
      for (uint32_t i = 0; i < c.set_layouts.size(); ++i)
        if (!c.set_layouts[i].name.empty() && c.set_layouts[i].name == name) return i;
      return std::nullopt;
    });
    if (!found) {
      return Error{ErrorCode::not_found,
                   "no resource signature named '" + std::string(name) + "'" +
                       did_you_mean(name, state_->names_of({ObjectKind::resource_signature}))};
    }
    if (auto it = state_->signature_by_layout.find(*found); it != state_->signature_by_layout.end())
      return it->second;
    auto layout = state_->set_layout(found->first, found->second, name);
    if (!layout) return layout.error();
    const format::SetLayout& stored = state_->archives[found->first].contents().set_layouts[found->second];
    UnpackedSignature& sig = state_->signatures.emplace_back();
    sig.name = stored.name;
    sig.layout = *layout;
    sig.set = stored.binding_index;
    for (const auto& b : stored.bindings)
      sig.bindings.push_back({b.name, stored.binding_index, b.binding,
                              static_cast<VkDescriptorType>(b.descriptor_type), b.count, b.stage_flags,
                              state_->immutable_sampler_of(found->first, b)});
    state_->signature_by_layout.emplace(*found, &sig);
    return &sig;
  });
}

Result<VkRenderPass> Dearchiver::unpack_render_pass(std::string_view name) {
  return api_guard("Dearchiver::unpack_render_pass", [&]() -> Result<VkRenderPass> {
    std::lock_guard lock(state_->mutex);
    auto found = state_->find_named([&](const format::Contents& c) -> std::optional<uint32_t> {
      for (uint32_t i = 0; i < c.render_passes.size(); ++i)
        if (c.render_passes[i].name == name) return i;
      return std::nullopt;
    });
    if (!found) {
      return Error{ErrorCode::not_found, "no render pass named '" + std::string(name) + "'" +
                                             did_you_mean(name, state_->names_of({ObjectKind::render_pass}))};
    }
    return state_->render_pass(found->first, found->second);
  });
}

Result<UnpackedShader> Dearchiver::unpack_shader(std::string_view name) {
  return api_guard("Dearchiver::unpack_shader", [&]() -> Result<UnpackedShader> {
    std::lock_guard lock(state_->mutex);
    auto found = state_->find_named([&](const format::Contents& c) -> std::optional<uint32_t> {
      auto it = std::lower_bound(c.standalone_shaders.begin(), c.standalone_shaders.end(), name,
                                 [&](uint32_t s, std::string_view n) { return c.shaders[s].name < n; });
      if (it != c.standalone_shaders.end() && c.shaders[*it].name == name) return *it;
      return std::nullopt;
    });
    if (!found) {
      return Error{ErrorCode::not_found, "no standalone shader named '" + std::string(name) + "'" +
                                             did_you_mean(name, state_->names_of({ObjectKind::shader}))};
    }
    const format::Shader& shader = state_->archives[found->first].contents().shaders[found->second];
    auto module = state_->module(found->first, shader.blob, shader.name);
    if (!module) return module.error();
    return UnpackedShader{shader.name, *module, static_cast<VkShaderStageFlagBits>(shader.stage),
                          shader.entry_point};
  });
}

const char* to_string(ErrorCode code) {
  switch (code) {
    case ErrorCode::io_error:
      return "io_error";
    case ErrorCode::bad_magic:
      return "bad_magic";
    case ErrorCode::unsupported_version:
      return "unsupported_version";
    case ErrorCode::truncated:
      return "truncated";
    case ErrorCode::corrupt:
      return "corrupt";
    case ErrorCode::checksum_mismatch:
      return "checksum_mismatch";
    case ErrorCode::content_version_mismatch:
      return "content_version_mismatch";
    case ErrorCode::misaligned_memory:
      return "misaligned_memory";
    case ErrorCode::not_found:
      return "not_found";
    case ErrorCode::wrong_type:
      return "wrong_type";
    case ErrorCode::missing_backend:
      return "missing_backend";
    case ErrorCode::unsupported:
      return "unsupported";
    case ErrorCode::vulkan_error:
      return "vulkan_error";
    case ErrorCode::invalid_argument:
      return "invalid_argument";
    case ErrorCode::out_of_memory:
      return "out_of_memory";
  }
  return "unknown";
}

}  // namespace statepack
