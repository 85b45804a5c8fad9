// What the device allows, checked before any vkCreate* call: values beyond a device limit are
// undefined behaviour in Vulkan, and drivers (lavapipe among them) trust them, allocating gigabytes
// for an absurd push constant size or crashing on a missing set. Each error names the object, the
// value and the limit.
#pragma once

#include <vulkan/vulkan.h>

#include <array>
#include <atomic>
#include <functional>
#include <optional>
#include <string>
#include <string_view>

#include "format/archive_format.hpp"
#include "format/spirv_walk.hpp"
#include "vulkan_functions.hpp"

namespace statepack::detail {

// The device as the runtime sees it: its entry points (loaded once, from the application's dispatch),
// limits and formats.
struct DeviceCaps {
  VkPhysicalDevice physical_device = VK_NULL_HANDLE;
  VkPhysicalDeviceProperties properties{};
  VulkanFunctions vk;

  // Thread-safe (Vulkan allows concurrent physical-device queries). The core formats are asked once
  // each: every pipeline checks its targets and vertex formats, a load of 100 asked the driver 100 times.
  VkFormatProperties format(uint32_t format) const;

 private:
  static constexpr uint32_t kCachedFormats = 185;  // VK_FORMAT_UNDEFINED .. VK_FORMAT_ASTC_12x12_SRGB_BLOCK
  struct CachedFormat {
    std::atomic<bool> known{false};  // set (release) after the three fields (relaxed)
    std::atomic<VkFormatFeatureFlags> linear{0}, optimal{0}, buffer{0};
  };
  mutable std::array<CachedFormat, kCachedFormats> formats_;
};

// A descriptor set layout on its own (signatures, and each set of a pipeline).
Result<void> check_set_layout(const format::SetLayout& layout, const DeviceCaps& caps,
                              std::string_view owner);

// A render pass: attachment formats, sample counts and layouts, attachments per subpass, and
// dependencies (stage and access masks that agree, features for the stages they name).
Result<void> check_render_pass(const format::RenderPass& pass, const DeviceCaps& caps,
                               const VkPhysicalDeviceFeatures& features);

// An immutable sampler: anisotropy, LOD bias and the rules for unnormalized coordinates.
Result<void> check_sampler(const format::Sampler& sampler, const DeviceCaps& caps, std::string_view owner);

// A pipeline's layout and shaders (SPIR-V version, sets, descriptors per stage and per layout,
// push constants).
Result<void> check_pipeline_layout(const format::Contents& contents, const format::Pipeline& pipeline,
                                   const DeviceCaps& caps);

// A compute shader's work-group size, with the values the pipeline's specialization constants give it
// (`specialized(spec_id)`: the value set for that SpecId, if any), against the device's
// maxComputeWorkGroupSize and maxComputeWorkGroupInvocations (VUID-RuntimeSpirv-x-06429 to -06432).
// `unsupported` beyond them; `invalid_argument` for a dimension of 0 (only a specialization can set it).
Result<void> check_workgroup_size(const std::string& pipeline, const spirv::EntryPoint& entry,
                                  const std::function<std::optional<uint32_t>(uint32_t)>& specialized,
                                  const VkPhysicalDeviceLimits& limits);

// A graphics pipeline's fixed-function state after the modify callback: vertex input, attachments,
// samples, blending.
struct GraphicsTargets {
  uint32_t color_count = 0;
  const VkFormat* color_formats = nullptr;
  VkFormat depth_stencil_format = VK_FORMAT_UNDEFINED;
  VkSampleCountFlagBits samples = VK_SAMPLE_COUNT_1_BIT;
  const bool* blend_enabled = nullptr;  // color_count entries
  // Bit i: the modify callback set render target i's format (or added the target). A format there that
  // does not fit the shader is then the caller's mistake (invalid_argument), not the archive's (corrupt).
  uint32_t patched_targets = 0;
};
// The walked module of a blob (walked once per archive by the caller; every blob walked at load).
using ModuleOf = std::function<const spirv::Module*(uint32_t blob)>;
Result<void> check_graphics_state(const format::Contents& contents, const format::Pipeline& pipeline,
                                  const GraphicsTargets& targets, const DeviceCaps& caps,
                                  const ModuleOf& module_of);

}  // namespace statepack::detail
