// Dearchiver: turns archived pipelines into Vulkan objects, sharing modules and set layouts.
#include "statepack/dearchiver.hpp"

#include <algorithm>
#include <deque>
#include <map>
#include <mutex>
#include <tuple>

#include "statepack/archive_format.hpp"
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

PatchableState to_patchable(const format::GraphicsState& g) {
  PatchableState s;
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
  std::vector<Archive> archives;
  std::map<std::pair<size_t, uint32_t>, VkShaderModule> modules;             // (archive, blob)
  std::map<std::pair<size_t, uint32_t>, VkDescriptorSetLayout> set_layouts;  // (archive, layout)
  VkDescriptorSetLayout empty_set_layout = VK_NULL_HANDLE;  // fills holes in the set numbering
  // (set layouts, push constant size, push constant stages) -> layout
  std::map<std::tuple<std::vector<VkDescriptorSetLayout>, uint32_t, uint32_t>, VkPipelineLayout>
      pipeline_layouts;
  std::deque<UnpackedPipeline> pipelines;                                  // stable addresses
  std::map<std::string, const UnpackedPipeline*, std::less<>> unmodified;  // cache by name
  std::mutex mutex;

  ~State() {
    VkDevice device = context.device;
    const VkAllocationCallbacks* alloc = context.allocator;
    for (auto& p : pipelines) vkDestroyPipeline(device, p.pipeline, alloc);
    for (auto& [key, layout] : pipeline_layouts) vkDestroyPipelineLayout(device, layout, alloc);
    for (auto& [key, layout] : set_layouts) vkDestroyDescriptorSetLayout(device, layout, alloc);
    if (empty_set_layout) vkDestroyDescriptorSetLayout(device, empty_set_layout, alloc);
    for (auto& [key, module] : modules) vkDestroyShaderModule(device, module, alloc);
  }

  struct Found {
    size_t archive;
    const format::Pipeline* pipeline;
  };

  std::vector<std::string> all_names() const {
    std::vector<std::string> names;
    for (const auto& a : archives)
      for (const auto& p : a.contents().pipelines) names.push_back(p.name);
    return names;
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
    std::vector<VkDescriptorSetLayoutBinding> bindings;
    for (const auto& b : stored.bindings)
      bindings.push_back(
          {b.binding, static_cast<VkDescriptorType>(b.descriptor_type), b.count, b.stage_flags, nullptr});
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

  // Everything but the VkPipeline: layout, set layouts, binding table, shader stages.
  struct Prepared {
    UnpackedPipeline out;
    std::vector<VkPipelineShaderStageCreateInfo> stages;
  };

  Result<Prepared> prepare(const Found& found) {
    const format::Pipeline& p = *found.pipeline;
    const auto& contents = archives[found.archive].contents();
    if (!(contents.backends & format::kBackendVulkan))
      return Error{ErrorCode::missing_backend, "pipeline '" + p.name + "': the archive has no Vulkan data"};
    Prepared prepared;
    UnpackedPipeline& out = prepared.out;
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
                                b.count, b.stage_flags});
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
    for (uint32_t s : p.shaders) {
      const format::Shader& shader = contents.shaders[s];
      auto module = this->module(found.archive, shader.blob, shader.name);
      if (!module) return module.error();
      VkPipelineShaderStageCreateInfo stage{VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO};
      stage.stage = static_cast<VkShaderStageFlagBits>(shader.stage);
      stage.module = *module;
      stage.pName = shader.entry_point.c_str();
      prepared.stages.push_back(stage);
    }
    return prepared;
  }

  const UnpackedPipeline* keep(UnpackedPipeline pipeline, bool cacheable) {
    pipelines.push_back(std::move(pipeline));
    const UnpackedPipeline* kept = &pipelines.back();
    if (cacheable) unmodified.emplace(kept->name, kept);
    return kept;
  }
};

Dearchiver::Dearchiver(std::unique_ptr<State> state) : state_(std::move(state)) {}
Dearchiver::Dearchiver(Dearchiver&&) noexcept = default;
Dearchiver& Dearchiver::operator=(Dearchiver&&) noexcept = default;
Dearchiver::~Dearchiver() = default;

Result<Dearchiver> Dearchiver::create(const DeviceContext& context) {
  if (context.device == VK_NULL_HANDLE || context.physical_device == VK_NULL_HANDLE)
    return Error{ErrorCode::invalid_argument, "Dearchiver::create needs a VkPhysicalDevice and a VkDevice"};
  auto state = std::make_unique<State>();
  state->context = context;
  return Dearchiver(std::move(state));
}

Result<void> Dearchiver::add_archive(Archive archive) {
  std::lock_guard lock(state_->mutex);
  state_->archives.push_back(std::move(archive));
  return {};
}

std::vector<std::string> Dearchiver::pipeline_names() const {
  std::lock_guard lock(state_->mutex);
  return state_->all_names();
}

Result<const UnpackedPipeline*> Dearchiver::unpack_compute(std::string_view name) {
  std::lock_guard lock(state_->mutex);
  if (auto it = state_->unmodified.find(name); it != state_->unmodified.end()) {
    if (it->second->bind_point == VK_PIPELINE_BIND_POINT_COMPUTE) return it->second;
  }
  auto found = state_->find(name, format::PipelineKind::compute);
  if (!found) return found.error();
  auto prepared = state_->prepare(*found);
  if (!prepared) return prepared.error();
  UnpackedPipeline& out = prepared->out;
  out.bind_point = VK_PIPELINE_BIND_POINT_COMPUTE;
  VkComputePipelineCreateInfo info{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
  info.stage = prepared->stages.at(0);
  info.layout = out.layout;
  VkResult r = vkCreateComputePipelines(state_->context.device, state_->context.pipeline_cache, 1, &info,
                                        state_->context.allocator, &out.pipeline);
  if (r != VK_SUCCESS) return vulkan_failure("vkCreateComputePipelines", r, out.name);
  return state_->keep(std::move(out), true);
}

Result<const UnpackedPipeline*> Dearchiver::unpack_graphics(std::string_view name,
                                                            const ModifyCallback& modify) {
  std::lock_guard lock(state_->mutex);
  if (!modify) {
    if (auto it = state_->unmodified.find(name); it != state_->unmodified.end()) {
      if (it->second->bind_point == VK_PIPELINE_BIND_POINT_GRAPHICS) return it->second;
    }
  }
  auto found = state_->find(name, format::PipelineKind::graphics);
  if (!found) return found.error();
  if (!state_->context.dynamic_rendering_enabled)
    return Error{
        ErrorCode::unsupported,
        "pipeline '" + std::string(name) + "' uses dynamic rendering, which the device was not created with"};
  auto prepared = state_->prepare(*found);
  if (!prepared) return prepared.error();
  UnpackedPipeline& out = prepared->out;
  out.bind_point = VK_PIPELINE_BIND_POINT_GRAPHICS;

  const format::GraphicsState& g = found->pipeline->graphics;
  PatchableState s = to_patchable(g);
  if (modify) modify(s);
  if (s.color_count > s.color_formats.size())
    return Error{ErrorCode::invalid_argument, "pipeline '" + out.name + "': the modify callback set " +
                                                  std::to_string(s.color_count) +
                                                  " render targets (at most 8)"};

  VkPipelineVertexInputStateCreateInfo vertex_input{
      VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO};
  VkPipelineInputAssemblyStateCreateInfo assembly{
      VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO};
  assembly.topology = static_cast<VkPrimitiveTopology>(g.topology);
  VkPipelineViewportStateCreateInfo viewport{VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO};
  viewport.viewportCount = 1;
  viewport.scissorCount = 1;
  VkPipelineRasterizationStateCreateInfo raster{VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO};
  raster.depthClampEnable = s.rasterizer.depth_clamp;
  raster.polygonMode = s.rasterizer.polygon_mode;
  raster.cullMode = s.rasterizer.cull_mode;
  raster.frontFace = s.rasterizer.front_face;
  raster.depthBiasEnable = s.rasterizer.depth_bias != 0 || s.rasterizer.depth_bias_slope != 0;
  raster.depthBiasConstantFactor = s.rasterizer.depth_bias;
  raster.depthBiasClamp = s.rasterizer.depth_bias_clamp;
  raster.depthBiasSlopeFactor = s.rasterizer.depth_bias_slope;
  raster.lineWidth = 1.0f;
  VkPipelineMultisampleStateCreateInfo multisample{VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO};
  multisample.rasterizationSamples = s.samples;
  VkSampleMask sample_mask = g.sample_mask;
  multisample.pSampleMask = &sample_mask;
  multisample.alphaToCoverageEnable = g.alpha_to_coverage;
  const bool depth_attachment = has_depth(s.depth_stencil_format);
  const bool stencil_attachment = has_stencil(s.depth_stencil_format);
  VkPipelineDepthStencilStateCreateInfo depth{VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO};
  depth.depthTestEnable = depth_attachment && s.depth_stencil.depth_test;
  depth.depthWriteEnable = depth_attachment && s.depth_stencil.depth_write;
  depth.depthCompareOp = s.depth_stencil.depth_compare;
  depth.stencilTestEnable = stencil_attachment && s.depth_stencil.stencil_test;
  depth.front = s.depth_stencil.front;
  depth.back = s.depth_stencil.back;
  depth.maxDepthBounds = 1.0f;
  std::array<VkPipelineColorBlendAttachmentState, 8> attachments{};
  for (uint32_t i = 0; i < s.color_count; ++i) {
    const auto& b = s.blend[i];
    attachments[i] = {b.enable,    b.src_color, b.dst_color, b.color_op,
                      b.src_alpha, b.dst_alpha, b.alpha_op,  b.write_mask};
  }
  VkPipelineColorBlendStateCreateInfo blend{VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO};
  blend.attachmentCount = s.color_count;
  blend.pAttachments = attachments.data();
  const VkDynamicState dynamic_states[] = {VK_DYNAMIC_STATE_VIEWPORT, VK_DYNAMIC_STATE_SCISSOR};
  VkPipelineDynamicStateCreateInfo dynamic{VK_STRUCTURE_TYPE_PIPELINE_DYNAMIC_STATE_CREATE_INFO};
  dynamic.dynamicStateCount = 2;
  dynamic.pDynamicStates = dynamic_states;
  VkPipelineRenderingCreateInfo rendering{VK_STRUCTURE_TYPE_PIPELINE_RENDERING_CREATE_INFO};
  rendering.colorAttachmentCount = s.color_count;
  rendering.pColorAttachmentFormats = s.color_formats.data();
  rendering.depthAttachmentFormat = depth_attachment ? s.depth_stencil_format : VK_FORMAT_UNDEFINED;
  rendering.stencilAttachmentFormat = stencil_attachment ? s.depth_stencil_format : VK_FORMAT_UNDEFINED;

  VkGraphicsPipelineCreateInfo info{VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO};
  info.pNext = &rendering;
  info.stageCount = static_cast<uint32_t>(prepared->stages.size());
  info.pStages = prepared->stages.data();
  info.pVertexInputState = &vertex_input;
  info.pInputAssemblyState = &assembly;
  info.pViewportState = &viewport;
  info.pRasterizationState = &raster;
  info.pMultisampleState = &multisample;
  info.pDepthStencilState = &depth;
  info.pColorBlendState = &blend;
  info.pDynamicState = &dynamic;
  info.layout = out.layout;
  VkResult r = vkCreateGraphicsPipelines(state_->context.device, state_->context.pipeline_cache, 1, &info,
                                         state_->context.allocator, &out.pipeline);
  if (r != VK_SUCCESS) return vulkan_failure("vkCreateGraphicsPipelines", r, out.name);
  return state_->keep(std::move(out), !modify);
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
  }
  return "unknown";
}

}  // namespace statepack
