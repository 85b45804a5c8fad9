// Turning an archived pipeline into Vulkan create-info structs: the modify callback's state settled and
// checked against the spec and the device, the shared objects made through the ObjectCache, every field
// filled. Creating the pipeline from a plan is the Dearchiver's (it may create plans on several threads).
#pragma once

#include <array>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "device_limits.hpp"
#include "format/archive_format.hpp"
#include "object_cache.hpp"
#include "statepack/dearchiver.hpp"

namespace statepack::detail {

// A pipeline of one of the Dearchiver's archives.
struct ArchivedPipeline {
  size_t archive;
  const format::Pipeline* pipeline;
};

// A pipeline ready to create: every shared object exists and every create-info field is filled.
// Heap-allocated so the pointers between the structs stay valid.
struct Plan {
  UnpackedPipeline out;
  ArchivedPipeline source{0, nullptr};  // what it was planned from
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
  VkPipelineMultisampleStateCreateInfo multisample{VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO};
  VkSampleMask sample_mask = 0xFFFFFFFFu;
  VkPipelineDepthStencilStateCreateInfo depth{VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO};
  std::array<VkPipelineColorBlendAttachmentState, 8> attachments{};
  VkPipelineColorBlendStateCreateInfo blend{VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO};
  struct StageConstants {
    std::vector<VkSpecializationMapEntry> entries;
    std::vector<uint8_t> data;
    VkSpecializationInfo info{};
  };
  // One per stage, in the order of `stages`: a pipeline has at most six (VERTEX..COMPUTE, one shader per
  // stage, checked at load), and a fixed array costs no allocation and never moves what points into it.
  std::array<StageConstants, 6> constants;
  VkPipelineDynamicStateCreateInfo dynamic{VK_STRUCTURE_TYPE_PIPELINE_DYNAMIC_STATE_CREATE_INFO};
  VkPipelineRenderingCreateInfo rendering{VK_STRUCTURE_TYPE_PIPELINE_RENDERING_CREATE_INFO};
  VkGraphicsPipelineCreateInfo graphics{VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO};
  // VK_EXT_pipeline_creation_feedback, chained in front of the create info's pNext when the device has it.
  VkPipelineCreationFeedback feedback{};
  VkPipelineCreationFeedbackCreateInfo feedback_info{
      VK_STRUCTURE_TYPE_PIPELINE_CREATION_FEEDBACK_CREATE_INFO};
};

class Planner {
 public:
  Planner(const DeviceContext& context, const DeviceCaps& caps, const VkPhysicalDeviceFeatures& features,
          ObjectCache& cache)
      : context_(context), caps_(caps), features_(features), cache_(cache) {}

  // The state is settled and checked first, so that nothing is created for a pipeline that fails.
  Result<std::unique_ptr<Plan>> plan_graphics(const ArchivedPipeline& found, const ModifyCallback& modify);
  // Only the constants of a compute pipeline's state apply.
  Result<std::unique_ptr<Plan>> plan_compute(const ArchivedPipeline& found, const ModifyCallback& modify);
  // The compute shader's work-group size with the settled constants, against the device's limits.
  Result<void> check_compute_size(const ArchivedPipeline& found,
                                  const std::vector<SpecializationConstant>& constants);

 private:
  // Layout, set layouts, binding table and shader stages: what both kinds of pipeline need.
  Result<std::unique_ptr<Plan>> plan_common(const ArchivedPipeline& found,
                                            const std::vector<SpecializationConstant>& constants);
  // A graphics pipeline's state after the callback, checked: the callback's values, render targets
  // for every location the pixel shader writes, no UNKNOWN format left.
  Result<PatchableState> settle_graphics(const ArchivedPipeline& found, const ModifyCallback& modify);
  // The settled state against the device: features, topology and tessellation, render pass, limits.
  std::optional<Error> check_graphics(const ArchivedPipeline& found, const PatchableState& settled);
  void plan_vertex_input(const ArchivedPipeline& found, Plan& plan);
  static void plan_fixed_function(const format::GraphicsState& g, uint32_t dynamic_mask, Plan& plan);
  // The dynamic states a callback settled: each one statepack supports and the device has, viewport and
  // scissor included, none twice. Returns them as the archive's bit mask.
  Result<uint32_t> settle_dynamic_states(const std::string& name, std::vector<VkDynamicState>& states);
  // The device features a graphics state needs, checked against the enabled ones.
  std::optional<Error> check_features(const std::string& name, const PatchableState& s);
  [[gnu::cold]] static Error missing_feature(std::string_view pipeline, const char* feature);
  static std::optional<Error> run_modify(const std::string& pipeline, const ModifyCallback& modify,
                                         PatchableState& state);

  const DeviceContext& context_;
  const DeviceCaps& caps_;
  const VkPhysicalDeviceFeatures& features_;
  ObjectCache& cache_;
};

}  // namespace statepack::detail
