#include "pipeline_plan.hpp"

#include "support/failure.hpp"

#include <algorithm>
#include <bit>
#include <exception>
#include <new>
#include <unordered_map>

#include "format/spirv_walk.hpp"
#include "patchable_state.hpp"
#include "patched_state_check.hpp"
#include "vk_result_string.hpp"

namespace statepack::detail {
namespace {

bool has_stencil(VkFormat format) {
  return format == VK_FORMAT_S8_UINT || format == VK_FORMAT_D16_UNORM_S8_UINT ||
         format == VK_FORMAT_D24_UNORM_S8_UINT || format == VK_FORMAT_D32_SFLOAT_S8_UINT;
}
bool has_depth(VkFormat format) {
  return format != VK_FORMAT_UNDEFINED && format != VK_FORMAT_S8_UINT;
}

}  // namespace

Result<std::unique_ptr<Plan>> Planner::plan_common(const ArchivedPipeline& found,
                                                   const std::vector<SpecializationConstant>& constants) {
  const format::Pipeline& p = *found.pipeline;
  const auto& contents = cache_.contents(found.archive);
  if (!(contents.backends & format::kBackendVulkan))
    return detail::failure(ErrorCode::missing_backend,
                           "pipeline '" + p.name + "': the archive has no Vulkan data");
  if (auto ok = check_pipeline_layout(contents, p, caps_); !ok) return ok.error();
  // Default-initialised, not value-initialised: every member has its initialiser, and zeroing the whole
  // plan first cost each pipeline a few hundred instructions.
  std::unique_ptr<Plan> plan(new Plan);
  plan->source = found;
  UnpackedPipeline& out = plan->out;
  out.name = p.name;
  out.push_constant_size = p.push_constant_size;
  out.push_constant_stages = p.push_constant_stages;
  out.set_layouts.reserve(p.set_layouts.size());
  plan->stages.reserve(p.shaders.size());
  for (uint32_t set = 0; set < p.set_layouts.size(); ++set) {
    auto layout = cache_.set_layout(found.archive, p.set_layouts[set], p.name);
    if (!layout) return layout.error();
    out.set_layouts.push_back(*layout);
    if (p.set_layouts[set] == format::kNone) continue;
    for (const auto& b : contents.set_layouts[p.set_layouts[set]].bindings)
      out.bindings.push_back({b.name, set, b.binding, static_cast<VkDescriptorType>(b.descriptor_type),
                              b.count, b.stage_flags, cache_.immutable_sampler_of(found.archive, b)});
  }
  auto layout = cache_.pipeline_layout(out.set_layouts, p.push_constant_size, p.push_constant_stages, p.name);
  if (!layout) return layout.error();
  out.layout = *layout;
  uint32_t stages = 0;
  if (p.shaders.size() > plan->constants.size())  // decode refuses two shaders for one stage
    return detail::failure(ErrorCode::corrupt,
                           "pipeline '" + p.name + "' has more shader stages than Vulkan has");
  std::unordered_map<std::string_view, const SpecializationConstant*> value_of;
  for (const auto& v : constants) value_of.emplace(v.name, &v);
  for (uint32_t s : p.shaders) {
    const format::Shader& shader = contents.shaders[s];
    auto module = cache_.module(found.archive, shader.blob, shader.name);
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
  if ((stages & VK_SHADER_STAGE_GEOMETRY_BIT) && !features_.geometryShader)
    return missing_feature(p.name, "geometryShader");
  if ((stages & (VK_SHADER_STAGE_TESSELLATION_CONTROL_BIT | VK_SHADER_STAGE_TESSELLATION_EVALUATION_BIT)) &&
      !features_.tessellationShader)
    return missing_feature(p.name, "tessellationShader");
  return plan;
}

Error Planner::missing_feature(std::string_view pipeline, const char* feature) {
  return detail::failure(ErrorCode::unsupported,
                         "pipeline '" + std::string(pipeline) + "' needs the device feature '" + feature +
                             "', which is not enabled (DeviceContext::enabled_features says "
                             "what the device was created with)");
}

// Runs the caller's callback. What it throws becomes an error naming the pipeline, here, so that an
// unpack_all caller learns which pipeline's patch failed; bad_alloc goes on to api_guard
// (out_of_memory), as for the library's own allocations.
std::optional<Error> Planner::run_modify(const std::string& pipeline, const ModifyCallback& modify,
                                         PatchableState& state) {
  try {
    modify(state);
    return std::nullopt;
  } catch (const std::bad_alloc&) {
    throw;
  } catch (const std::exception& e) {
    return detail::failure(ErrorCode::invalid_argument,
                           "pipeline '" + pipeline + "': the modify callback threw: " + e.what());
  } catch (...) {
    return detail::failure(ErrorCode::invalid_argument,
                           "pipeline '" + pipeline + "': the modify callback threw");
  }
}

Result<void> Planner::check_compute_size(const ArchivedPipeline& found,
                                         const std::vector<SpecializationConstant>& constants) {
  const format::Pipeline& p = *found.pipeline;
  const auto& contents = cache_.contents(found.archive);
  if (p.shaders.empty()) return {};
  const format::Shader& shader = contents.shaders[p.shaders[0]];
  const spirv::Module* module = cache_.walked(found.archive, shader.blob);
  const spirv::EntryPoint* entry =
      module ? module->find(*spirv::execution_model_of_stage(VK_SHADER_STAGE_COMPUTE_BIT), shader.entry_point)
             : nullptr;
  if (!entry) return {};  // checked at load
  // The value the pipeline gives a SpecId: its constant of the compute stage with that id, as settled
  // (after the modify callback).
  auto specialized = [&](uint32_t spec_id) -> std::optional<uint32_t> {
    for (const auto& k : p.constants) {
      if (k.stage != VK_SHADER_STAGE_COMPUTE_BIT || k.constant_id != spec_id || k.size != 4) continue;
      for (const auto& v : constants)
        if (v.name == k.name) return v.get<uint32_t>();
    }
    return std::nullopt;
  };
  return check_workgroup_size(p.name, *entry, specialized, caps_.properties.limits);
}

Result<std::unique_ptr<Plan>> Planner::plan_compute(const ArchivedPipeline& found,
                                                    const ModifyCallback& modify) {
  // Only the constants apply to a compute pipeline; without a callback they are the archived ones.
  auto settle = [&]() -> Result<std::vector<SpecializationConstant>> {
    if (!modify) return constants_of(*found.pipeline);
    PatchableState settled = to_patchable(*found.pipeline);
    if (auto thrown = run_modify(found.pipeline->name, modify, settled)) return *thrown;
    return settle_constants(*found.pipeline, std::move(settled.constants));
  };
  auto constants = settle();
  if (!constants) return constants.error();
  if (auto ok = check_compute_size(found, *constants); !ok) return ok.error();
  auto plan = plan_common(found, *constants);
  if (!plan) return plan.error();
  Plan& pl = **plan;
  pl.cacheable = !modify;
  pl.state.constants = *constants;  // what a variants file records of a compute pipeline
  pl.out.bind_point = VK_PIPELINE_BIND_POINT_COMPUTE;
  pl.compute.stage = pl.stages.at(0);
  pl.compute.layout = pl.out.layout;
  return plan;
}

Result<PatchableState> Planner::settle_graphics(const ArchivedPipeline& found, const ModifyCallback& modify) {
  const std::string& name = found.pipeline->name;
  const bool uses_render_pass = found.pipeline->render_pass != format::kNone;
  // The state is settled and checked first, so that nothing is created for a pipeline that fails.
  PatchableState settled = to_patchable(*found.pipeline);
  const format::Shader* pixel_shader = nullptr;
  for (uint32_t index : found.pipeline->shaders)
    if (cache_.contents(found.archive).shaders[index].stage == VK_SHADER_STAGE_FRAGMENT_BIT)
      pixel_shader = &cache_.contents(found.archive).shaders[index];
  if (pixel_shader)
    if (const spirv::Module* module = cache_.walked(found.archive, pixel_shader->blob))
      settled.written_color_targets = module->output_location_mask();
  const uint32_t written = settled.written_color_targets;  // what the callback does to it is ignored
  if (modify) {
    const PatchableState before = settled;
    if (auto thrown = run_modify(name, modify, settled)) return *thrown;
    if (uses_render_pass &&
        (settled.color_count != before.color_count || settled.color_formats != before.color_formats ||
         settled.depth_stencil_format != before.depth_stencil_format || settled.samples != before.samples))
      return detail::failure(ErrorCode::invalid_argument,
                             "pipeline '" + name +
                                 "' uses a render pass, which fixes its attachment formats and "
                                 "sample count; the modify callback may not change them");
  }
  // Every value the callback left is checked as the archive's were at load, before any reaches Vulkan.
  if (modify)
    if (auto bad = check_patched_state(name, settled)) return *bad;
  // The notation may leave render targets to run time (pack notes it); what the pixel shader writes
  // must have a target once the callback has run, or the picture would silently stay blank.
  if (const uint32_t beyond = written & ~uint32_t((1ull << std::min(settled.color_count, 32u)) - 1))
    return detail::failure(ErrorCode::invalid_argument,
                           "pipeline '" + name + "': its pixel shader '" + pixel_shader->name +
                               "' writes render target " + std::to_string(std::countr_zero(beyond)) +
                               ", but the pipeline has " + std::to_string(settled.color_count) +
                               " render target(s): the notation leaves them to run time, so set "
                               "PatchableState::color_count (to at least " +
                               std::to_string(32 - std::countl_zero(written)) +
                               ") and color_formats in the modify callback, or give NumRenderTargets and "
                               "RTVFormats in the notation and pack again");
  // UNKNOWN in RTVFormats means "set at run time" (a swapchain's format): left unset, it is an error
  // rather than a pipeline silently created for VK_FORMAT_UNDEFINED.
  if (!uses_render_pass)
    for (uint32_t i = 0; i < settled.color_count; ++i)
      if (settled.color_formats[i] == VK_FORMAT_UNDEFINED)
        return detail::failure(
            ErrorCode::invalid_argument,
            "pipeline '" + name + "': render target " + std::to_string(i) +
                " is UNKNOWN (a format set at run time); set PatchableState::color_formats[" +
                std::to_string(i) + "] in the modify callback, or give RTVFormats[" + std::to_string(i) +
                "] in the notation and pack again");
  return settled;
}

std::optional<Error> Planner::check_graphics(const ArchivedPipeline& found, const PatchableState& settled) {
  const format::GraphicsState& g = found.pipeline->graphics;
  const std::string& name = found.pipeline->name;
  const bool uses_render_pass = found.pipeline->render_pass != format::kNone;
  if (auto missing = check_features(name, settled)) return missing;
  // Adjacency topologies need the geometry shader feature; patch lists go with tessellation, only.
  if (g.topology >= VK_PRIMITIVE_TOPOLOGY_LINE_LIST_WITH_ADJACENCY &&
      g.topology <= VK_PRIMITIVE_TOPOLOGY_TRIANGLE_STRIP_WITH_ADJACENCY && !features_.geometryShader)
    return missing_feature(name, "geometryShader");
  {
    bool tessellation = false;
    for (uint32_t index : found.pipeline->shaders)
      tessellation |=
          (cache_.contents(found.archive).shaders[index].stage &
           (VK_SHADER_STAGE_TESSELLATION_CONTROL_BIT | VK_SHADER_STAGE_TESSELLATION_EVALUATION_BIT)) != 0;
    if (tessellation != (g.topology == VK_PRIMITIVE_TOPOLOGY_PATCH_LIST))
      return detail::failure(ErrorCode::corrupt,
                             "pipeline '" + name + "' " +
                                 (tessellation ? "tessellates without" : "draws patches without") +
                                 " a patch list topology and tessellation shaders together");
    if (g.patch_control_points > caps_.properties.limits.maxTessellationPatchSize)
      return detail::failure(ErrorCode::unsupported,
                             "pipeline '" + name + "' has patches of " +
                                 std::to_string(g.patch_control_points) +
                                 " control points; the device allows " +
                                 std::to_string(caps_.properties.limits.maxTessellationPatchSize));
  }
  std::array<bool, 8> blend_enabled{};
  for (size_t i = 0; i < blend_enabled.size(); ++i) blend_enabled[i] = settled.blend[i].enable;
  GraphicsTargets targets{settled.color_count, settled.color_formats.data(), settled.depth_stencil_format,
                          settled.samples, blend_enabled.data()};
  // Slots whose format differs from the archive's were set by the callback (the archived state, read in
  // place: no second to_patchable copy).
  for (uint32_t i = 0; i < settled.color_count && i < settled.color_formats.size(); ++i)
    if (i >= g.color_count || uint32_t(settled.color_formats[i]) != g.color_formats[i])
      targets.patched_targets |= 1u << i;
  const auto& contents = cache_.contents(found.archive);
  if (uses_render_pass)
    if (auto ok = check_render_pass(contents.render_passes[found.pipeline->render_pass], caps_, features_);
        !ok)
      return ok.error();
  if (auto ok = check_graphics_state(contents, *found.pipeline, targets, caps_,
                                     [&](uint32_t blob) { return cache_.walked(found.archive, blob); });
      !ok)
    return ok.error();

  return std::nullopt;
}

// The vertex input: every binding, and the attributes the vertex shader reads.
void Planner::plan_vertex_input(const ArchivedPipeline& found, Plan& pl) {
  const format::GraphicsState& g = found.pipeline->graphics;
  const auto& contents = cache_.contents(found.archive);
  for (const auto& b : g.vertex_bindings)
    pl.vertex_bindings.push_back({b.binding, b.stride, static_cast<VkVertexInputRate>(b.input_rate)});
  // Attributes the vertex shader does not read have no effect; leaving them out keeps the layer
  // from warning about them (a re-sealed archive can add any).
  const spirv::Module* vertex_module = nullptr;
  for (uint32_t index : found.pipeline->shaders)
    if (contents.shaders[index].stage == VK_SHADER_STAGE_VERTEX_BIT)
      vertex_module = cache_.walked(found.archive, contents.shaders[index].blob);
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
}

// Input assembly, tessellation, viewport, rasterizer, multisample, depth-stencil, blend, dynamic states
// and dynamic-rendering formats, from the settled state in `pl.state`.
void Planner::plan_fixed_function(const format::GraphicsState& g, uint32_t dynamic_mask, Plan& pl) {
  const PatchableState& s = pl.state;
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
                              (dynamic_mask & format::kDynamicDepthBias) != 0;
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
  pl.depth.depthBoundsTestEnable = (dynamic_mask & format::kDynamicDepthBounds) != 0;
  for (uint32_t i = 0; i < s.color_count; ++i) {
    const auto& b = s.blend[i];
    pl.attachments[i] = {b.enable,    b.src_color, b.dst_color, b.color_op,
                         b.src_alpha, b.dst_alpha, b.alpha_op,  b.write_mask};
  }
  pl.blend.attachmentCount = s.color_count;
  pl.blend.pAttachments = pl.attachments.data();
  pl.dynamic.dynamicStateCount = static_cast<uint32_t>(s.dynamic_states.size());
  pl.dynamic.pDynamicStates = s.dynamic_states.data();  // the plan's own settled state: no copy
  pl.rendering.colorAttachmentCount = s.color_count;
  pl.rendering.pColorAttachmentFormats = s.color_formats.data();
  pl.rendering.depthAttachmentFormat = depth_attachment ? s.depth_stencil_format : VK_FORMAT_UNDEFINED;
  pl.rendering.stencilAttachmentFormat = stencil_attachment ? s.depth_stencil_format : VK_FORMAT_UNDEFINED;
}

Result<std::unique_ptr<Plan>> Planner::plan_graphics(const ArchivedPipeline& found,
                                                     const ModifyCallback& modify) {
  const format::GraphicsState& g = found.pipeline->graphics;
  const std::string& name = found.pipeline->name;
  const bool uses_render_pass = found.pipeline->render_pass != format::kNone;
  if (!uses_render_pass && !context_.dynamic_rendering_enabled)
    return detail::failure(
        ErrorCode::unsupported,
        "pipeline '" + name + "' uses dynamic rendering, which the device was not created with");
  // The state is settled and checked first, so that nothing is created for a pipeline that fails.
  auto settled_or = settle_graphics(found, modify);
  if (!settled_or) return settled_or.error();
  PatchableState& settled = *settled_or;
  if (auto bad = check_graphics(found, settled)) return *bad;
  auto dynamic_mask = settle_dynamic_states(name, settled.dynamic_states);
  if (!dynamic_mask) return dynamic_mask.error();
  auto constants = settle_constants(*found.pipeline, settled.constants);
  if (!constants) return constants.error();

  auto planned = plan_common(found, *constants);
  if (!planned) return planned.error();
  Plan& pl = **planned;
  pl.out.bind_point = VK_PIPELINE_BIND_POINT_GRAPHICS;
  pl.cacheable = !modify;
  pl.state = std::move(settled);
  VkRenderPass render_pass = VK_NULL_HANDLE;
  if (uses_render_pass) {
    auto pass = cache_.render_pass(found.archive, found.pipeline->render_pass);
    if (!pass) return pass.error();
    render_pass = *pass;
  }
  plan_vertex_input(found, pl);
  plan_fixed_function(g, *dynamic_mask, pl);

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

Result<uint32_t> Planner::settle_dynamic_states(const std::string& name,
                                                std::vector<VkDynamicState>& states) {
  uint32_t mask = 0;
  for (VkDynamicState state : states) {
    auto bit = dynamic_state_bit(state);
    if (!bit)
      return detail::failure(ErrorCode::unsupported, "pipeline '" + name + "': dynamic state " +
                                                         dynamic_state_name(state) +
                                                         " is not supported by the dearchiver");
    if ((*bit & format::kDynamicExtendedMask) && caps_.properties.apiVersion < VK_API_VERSION_1_3)
      return detail::failure(ErrorCode::unsupported,
                             "pipeline '" + name + "': dynamic state " + dynamic_state_name(state) +
                                 " needs Vulkan 1.3 (extended dynamic state), which the device lacks");
    if ((*bit & (format::kDynamicDepthBounds | (1u << 18))) && !features_.depthBounds)
      return missing_feature(name, "depthBounds");
    mask |= *bit;
  }
  if ((mask & format::kDynamicLegacy) != format::kDynamicLegacy)
    return detail::failure(
        ErrorCode::invalid_argument,
        "pipeline '" + name + "': viewport and scissor must stay dynamic (the modify callback removed one)");
  // Canonical order, duplicates gone: what Vulkan gets and what the callback of the next unpack sees.
  states.clear();
  for (uint32_t i = 0; i < 32; ++i)
    if (mask & (1u << i)) states.push_back(dynamic_state_of_bit(i));
  return mask;
}

std::optional<Error> Planner::check_features(const std::string& name, const PatchableState& s) {
  if (s.rasterizer.depth_clamp && !features_.depthClamp) return missing_feature(name, "depthClamp");
  if (s.rasterizer.polygon_mode != VK_POLYGON_MODE_FILL && !features_.fillModeNonSolid)
    return missing_feature(name, "fillModeNonSolid");
  if (s.rasterizer.depth_bias_clamp != 0 && !features_.depthBiasClamp)
    return missing_feature(name, "depthBiasClamp");
  for (uint32_t i = 0; i < s.color_count; ++i) {
    const auto& b = s.blend[i];
    auto dual = [](VkBlendFactor f) {
      return f >= VK_BLEND_FACTOR_SRC1_COLOR && f <= VK_BLEND_FACTOR_ONE_MINUS_SRC1_ALPHA;
    };
    // Dual-source factors need the feature even when blending is off (VUID-...-00608).
    if ((dual(b.src_color) || dual(b.dst_color) || dual(b.src_alpha) || dual(b.dst_alpha)) &&
        !features_.dualSrcBlend)
      return missing_feature(name, "dualSrcBlend");
    if (i > 0 && !features_.independentBlend && s.blend[i] != s.blend[0])
      return missing_feature(name, "independentBlend");
  }
  const VkPhysicalDeviceLimits& limits = caps_.properties.limits;  // queried once, at Dearchiver::create
  const VkSampleCountFlags counts =
      s.color_count > 0 ? limits.framebufferColorSampleCounts : limits.framebufferNoAttachmentsSampleCounts;
  if (!(counts & s.samples))
    return detail::failure(ErrorCode::unsupported, "pipeline '" + name + "' renders with " +
                                                       std::to_string(s.samples) +
                                                       " samples, which the device does not support");
  return std::nullopt;
}

}  // namespace statepack::detail
