#include "device_limits.hpp"

#include "support/failure.hpp"

#include "vk_enum_names.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <optional>
#include <string>
#include <tuple>
#include <type_traits>
#include <vector>

#include "format/spirv_walk.hpp"

namespace statepack::detail {

namespace {

// The subject of a message ("pipeline 'x'", "pipeline 'x': render target 2"), made only when a check
// fails: made for every check, these words cost a load of 100 pipelines a tenth of its own time. A
// non-owning reference to a callable, for parameters only (the callable outlives the call).
class Lazy {
 public:
  template <class F>
  requires(!std::is_same_v<F, Lazy>)
      Lazy(const F& make)  // NOLINT(google-explicit-constructor): passed as a lambda at every call
      : object_(&make),
        // Cold: it runs only when a check fails, and every message built in it is then compiled for size.
        call_(
            [](const void* o) __attribute__((cold))->std::string { return (*static_cast<const F*>(o))(); }) {}
  std::string operator()() const { return call_(object_); }

 private:
  const void* object_;
  std::string (*call_)(const void*);
};

[[gnu::cold]] Error over_limit(const std::string& object, const std::string& what, uint64_t value,
                               const char* limit, uint64_t allowed) {
  return detail::failure(ErrorCode::unsupported, object + ": " + what + " is " + std::to_string(value) +
                                                     ", beyond the device's " + limit + " of " +
                                                     std::to_string(allowed));
}

// Descriptor totals by the limit classes of VkPhysicalDeviceLimits.
struct DescriptorTotals {
  uint64_t samplers = 0, uniform_buffers = 0, uniform_dynamic = 0, storage_buffers = 0, storage_dynamic = 0,
           sampled_images = 0, storage_images = 0, input_attachments = 0;
  void add(uint32_t type, uint64_t count) {
    switch (type) {
      case VK_DESCRIPTOR_TYPE_SAMPLER:
        samplers += count;
        break;
      case VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER:
        samplers += count, sampled_images += count;
        break;
      case VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE:
      case VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER:
        sampled_images += count;
        break;
      case VK_DESCRIPTOR_TYPE_STORAGE_IMAGE:
      case VK_DESCRIPTOR_TYPE_STORAGE_TEXEL_BUFFER:
        storage_images += count;
        break;
      case VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER:
        uniform_buffers += count;
        break;
      case VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER_DYNAMIC:
        uniform_buffers += count, uniform_dynamic += count;
        break;
      case VK_DESCRIPTOR_TYPE_STORAGE_BUFFER:
        storage_buffers += count;
        break;
      case VK_DESCRIPTOR_TYPE_STORAGE_BUFFER_DYNAMIC:
        storage_buffers += count, storage_dynamic += count;
        break;
      case VK_DESCRIPTOR_TYPE_INPUT_ATTACHMENT:
        input_attachments += count;
        break;
      default:
        break;
    }
  }
  uint64_t resources() const {
    return samplers + uniform_buffers + storage_buffers + sampled_images + storage_images + input_attachments;
  }
};

// Totals of a whole layout (the maxDescriptorSet* limits count every set of a pipeline layout).
Result<void> check_layout_totals(const DescriptorTotals& t, const VkPhysicalDeviceLimits& l, Lazy who) {
  const std::array<std::tuple<uint64_t, const char*, uint32_t>, 8> checks{{
      {t.samplers, "maxDescriptorSetSamplers", l.maxDescriptorSetSamplers},
      {t.uniform_buffers, "maxDescriptorSetUniformBuffers", l.maxDescriptorSetUniformBuffers},
      {t.uniform_dynamic, "maxDescriptorSetUniformBuffersDynamic", l.maxDescriptorSetUniformBuffersDynamic},
      {t.storage_buffers, "maxDescriptorSetStorageBuffers", l.maxDescriptorSetStorageBuffers},
      {t.storage_dynamic, "maxDescriptorSetStorageBuffersDynamic", l.maxDescriptorSetStorageBuffersDynamic},
      {t.sampled_images, "maxDescriptorSetSampledImages", l.maxDescriptorSetSampledImages},
      {t.storage_images, "maxDescriptorSetStorageImages", l.maxDescriptorSetStorageImages},
      {t.input_attachments, "maxDescriptorSetInputAttachments", l.maxDescriptorSetInputAttachments},
  }};
  for (auto [value, limit, allowed] : checks)
    if (value > allowed) return over_limit(who(), "the descriptor count", value, limit, allowed);
  return {};
}

Result<void> check_stage_totals(const DescriptorTotals& t, const VkPhysicalDeviceLimits& l, Lazy who) {
  const std::array<std::tuple<uint64_t, const char*, uint32_t>, 7> checks{{
      {t.samplers, "maxPerStageDescriptorSamplers", l.maxPerStageDescriptorSamplers},
      {t.uniform_buffers, "maxPerStageDescriptorUniformBuffers", l.maxPerStageDescriptorUniformBuffers},
      {t.storage_buffers, "maxPerStageDescriptorStorageBuffers", l.maxPerStageDescriptorStorageBuffers},
      {t.sampled_images, "maxPerStageDescriptorSampledImages", l.maxPerStageDescriptorSampledImages},
      {t.storage_images, "maxPerStageDescriptorStorageImages", l.maxPerStageDescriptorStorageImages},
      {t.input_attachments, "maxPerStageDescriptorInputAttachments", l.maxPerStageDescriptorInputAttachments},
      {t.resources(), "maxPerStageResources", l.maxPerStageResources},
  }};
  for (auto [value, limit, allowed] : checks)
    if (value > allowed) return over_limit(who(), "the descriptor count", value, limit, allowed);
  return {};
}

constexpr uint32_t kMaxBindingNumber = 65535;

bool supports(const VkFormatProperties& p, VkFormatFeatureFlags features) {
  return (p.optimalTilingFeatures & features) == features;
}

// The lowest Vulkan version that accepts a SPIR-V version.
uint32_t api_version_for_spirv(uint32_t spirv_version) {
  if (spirv_version <= 0x00010000u) return VK_API_VERSION_1_0;
  if (spirv_version <= 0x00010300u) return VK_API_VERSION_1_1;
  if (spirv_version <= 0x00010500u) return VK_API_VERSION_1_2;
  return VK_API_VERSION_1_3;
}

bool color_layout(uint32_t l) {
  return l == VK_IMAGE_LAYOUT_GENERAL || l == VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
}
bool depth_layout(uint32_t l) {
  return l == VK_IMAGE_LAYOUT_GENERAL || l == VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL ||
         l == VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL ||
         l == VK_IMAGE_LAYOUT_DEPTH_READ_ONLY_STENCIL_ATTACHMENT_OPTIMAL ||
         l == VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_STENCIL_READ_ONLY_OPTIMAL;
}
bool input_layout(uint32_t l) {
  return l == VK_IMAGE_LAYOUT_GENERAL || l == VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL ||
         l == VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL;
}
bool is_depth_format(uint32_t f) {
  return f >= VK_FORMAT_D16_UNORM && f <= VK_FORMAT_D32_SFLOAT_S8_UINT;
}
bool read_only_layout(uint32_t l) {
  return l == VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL ||
         l == VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL ||
         l == VK_IMAGE_LAYOUT_DEPTH_READ_ONLY_STENCIL_ATTACHMENT_OPTIMAL ||
         l == VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_STENCIL_READ_ONLY_OPTIMAL;
}

// Vulkan 1.0 pipeline stages and access flags (archives hold nothing newer), and which stages perform
// which accesses (the spec's "supported access types" table).
constexpr uint32_t kCoreStages = 0x1FFFF;
constexpr uint32_t kShaderStages =
    VK_PIPELINE_STAGE_VERTEX_SHADER_BIT | VK_PIPELINE_STAGE_TESSELLATION_CONTROL_SHADER_BIT |
    VK_PIPELINE_STAGE_TESSELLATION_EVALUATION_SHADER_BIT | VK_PIPELINE_STAGE_GEOMETRY_SHADER_BIT |
    VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT | VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT;
constexpr uint32_t kFramebufferStages =
    VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT | VK_PIPELINE_STAGE_EARLY_FRAGMENT_TESTS_BIT |
    VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT;
bool access_fits(uint32_t access, uint32_t stages) {
  if (access & ~0x1FFFFu) return false;
  if (stages & VK_PIPELINE_STAGE_ALL_COMMANDS_BIT) return true;
  if (stages & VK_PIPELINE_STAGE_ALL_GRAPHICS_BIT) stages |= 0x7FF & ~VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT;
  const std::pair<uint32_t, uint32_t> table[] = {
      {VK_ACCESS_INDIRECT_COMMAND_READ_BIT, VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT},
      {VK_ACCESS_INDEX_READ_BIT, VK_PIPELINE_STAGE_VERTEX_INPUT_BIT},
      {VK_ACCESS_VERTEX_ATTRIBUTE_READ_BIT, VK_PIPELINE_STAGE_VERTEX_INPUT_BIT},
      {VK_ACCESS_UNIFORM_READ_BIT, kShaderStages},
      {VK_ACCESS_INPUT_ATTACHMENT_READ_BIT, VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT},
      {VK_ACCESS_SHADER_READ_BIT, kShaderStages},
      {VK_ACCESS_SHADER_WRITE_BIT, kShaderStages},
      {VK_ACCESS_COLOR_ATTACHMENT_READ_BIT, VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT},
      {VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT, VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT},
      {VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_READ_BIT,
       VK_PIPELINE_STAGE_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT},
      {VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT,
       VK_PIPELINE_STAGE_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT},
      {VK_ACCESS_TRANSFER_READ_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT},
      {VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT},
      {VK_ACCESS_HOST_READ_BIT, VK_PIPELINE_STAGE_HOST_BIT},
      {VK_ACCESS_HOST_WRITE_BIT, VK_PIPELINE_STAGE_HOST_BIT},
  };
  for (auto [bit, allowed] : table)
    if ((access & bit) && !(stages & allowed)) return false;
  return true;  // MEMORY_READ and MEMORY_WRITE fit every stage
}

const char* numeric_name(spirv::Numeric n) {
  switch (n) {
    case spirv::Numeric::float_:
      return "float";
    case spirv::Numeric::sint:
      return "signed integer";
    case spirv::Numeric::uint:
      return "unsigned integer";
    case spirv::Numeric::other:
      break;
  }
  return "other";
}

// Shader interface variables and the formats they meet agree on the numeric type (else the layer
// warns that values are undefined). `patched`: the modify callback set this format, so a mismatch is
// the caller's (invalid_argument, saying so); else the archive's (corrupt: pack checks it).
Result<void> check_numeric(const std::vector<spirv::Input>& variables, uint32_t location, uint32_t format,
                           Lazy what, bool patched = false) {
  const ErrorCode code = patched ? ErrorCode::invalid_argument : ErrorCode::corrupt;
  const char* by = patched ? " (set by the modify callback)" : "";
  for (const auto& v : variables) {
    if (location < v.location || location >= uint64_t(v.location) + v.locations) continue;
    if (format == VK_FORMAT_UNDEFINED)
      return detail::failure(code, what() + " has no format" + by +
                                       ", but the shader's variable at location " + std::to_string(location) +
                                       " is there");
    const spirv::Numeric wanted = spirv::numeric_of_format(format);
    if (v.numeric != spirv::Numeric::other && wanted != spirv::Numeric::other && v.numeric != wanted)
      return detail::failure(code, what() + " has format " + vk_name(VkFormat(format)) + by +
                                       ", which holds " + numeric_name(wanted) +
                                       " values, but the shader's variable at location " +
                                       std::to_string(location) + " is " + numeric_name(v.numeric));
  }
  return {};
}

}  // namespace

VkFormatProperties DeviceCaps::format(uint32_t f) const {
  if (f < kCachedFormats) {
    CachedFormat& c = formats_[f];
    if (c.known.load(std::memory_order_acquire))
      return {c.linear.load(std::memory_order_relaxed), c.optimal.load(std::memory_order_relaxed),
              c.buffer.load(std::memory_order_relaxed)};
  }
  VkFormatProperties p{};
  vk.vkGetPhysicalDeviceFormatProperties(physical_device, static_cast<VkFormat>(f), &p);
  if (f < kCachedFormats) {  // two threads may both ask: they store the same values
    CachedFormat& c = formats_[f];
    c.linear.store(p.linearTilingFeatures, std::memory_order_relaxed);
    c.optimal.store(p.optimalTilingFeatures, std::memory_order_relaxed);
    c.buffer.store(p.bufferFeatures, std::memory_order_relaxed);
    c.known.store(true, std::memory_order_release);
  }
  return p;
}

Result<void> check_set_layout(const format::SetLayout& layout, const DeviceCaps& caps,
                              std::string_view owner) {
  DescriptorTotals totals;
  for (const auto& b : layout.bindings) {
    // Vulkan sets no limit on binding numbers, but drivers size a set layout by its largest one
    // (lavapipe fails with VK_ERROR_OUT_OF_HOST_MEMORY at 2^31), so a sparse absurd one is refused.
    if (b.binding > kMaxBindingNumber)
      return detail::failure(ErrorCode::unsupported, std::string(owner) + ": binding '" + b.name +
                                                         "' has the number " + std::to_string(b.binding) +
                                                         ", beyond the " + std::to_string(kMaxBindingNumber) +
                                                         " this dearchiver accepts");
    if (b.descriptor_type == VK_DESCRIPTOR_TYPE_INPUT_ATTACHMENT &&
        (b.stage_flags & ~VK_SHADER_STAGE_FRAGMENT_BIT))
      return detail::failure(ErrorCode::corrupt, std::string(owner) + ": input attachment '" + b.name +
                                                     "' is visible to stages other than the fragment stage");
    totals.add(b.descriptor_type, b.count);
  }
  return check_layout_totals(totals, caps.properties.limits, [&] { return std::string(owner); });
}

Result<void> check_dependencies(const format::RenderPass& pass, const VkPhysicalDeviceFeatures& features) {
  auto who = [&] { return "render pass '" + pass.name + "'"; };
  for (size_t i = 0; i < pass.dependencies.size(); ++i) {
    const auto& d = pass.dependencies[i];
    const std::string dependency = who() + ": dependency " + std::to_string(i);
    auto bad = [&](const std::string& why) {
      return detail::failure(ErrorCode::corrupt, dependency + " " + why);
    };
    if (d.src_subpass == format::kNone && d.dst_subpass == format::kNone)
      return bad("is external on both sides");
    if (d.src_subpass != format::kNone && d.dst_subpass != format::kNone && d.src_subpass > d.dst_subpass)
      return bad("goes from a later subpass to an earlier one");
    if (d.flags & ~uint32_t{VK_DEPENDENCY_BY_REGION_BIT}) return bad("has unsupported flags");
    for (uint32_t stages : {d.src_stages, d.dst_stages}) {
      if (stages == 0 || (stages & ~kCoreStages)) return bad("has an empty or unknown stage mask");
      if ((stages & VK_PIPELINE_STAGE_GEOMETRY_SHADER_BIT) && !features.geometryShader)
        return bad("names the geometry stage, but the geometryShader feature is not enabled");
      if ((stages & (VK_PIPELINE_STAGE_TESSELLATION_CONTROL_SHADER_BIT |
                     VK_PIPELINE_STAGE_TESSELLATION_EVALUATION_SHADER_BIT)) &&
          !features.tessellationShader)
        return bad("names a tessellation stage, but the tessellationShader feature is not enabled");
    }
    if (!access_fits(d.src_access, d.src_stages) || !access_fits(d.dst_access, d.dst_stages))
      return bad("has access flags that its stages do not perform");
    // A side inside the render pass runs in the graphics pipeline: compute, transfer and host stages
    // (and ALL_COMMANDS, which holds them) are only for the external side.
    constexpr uint32_t kNonGraphics = VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT |
                                      VK_PIPELINE_STAGE_HOST_BIT | VK_PIPELINE_STAGE_ALL_COMMANDS_BIT;
    if ((d.src_subpass != format::kNone && (d.src_stages & kNonGraphics)) ||
        (d.dst_subpass != format::kNone && (d.dst_stages & kNonGraphics)))
      return bad("names a stage outside the graphics pipeline for a subpass");
    if (d.src_subpass == d.dst_subpass &&
        ((d.src_stages | d.dst_stages) & ~kFramebufferStages || !(d.flags & VK_DEPENDENCY_BY_REGION_BIT)))
      return bad("is a self-dependency outside framebuffer-space stages or not by region");
  }
  return {};
}

Result<void> check_render_pass(const format::RenderPass& pass, const DeviceCaps& caps,
                               const VkPhysicalDeviceFeatures& features) {
  if (auto ok = check_dependencies(pass, features); !ok) return ok;
  const VkPhysicalDeviceLimits& l = caps.properties.limits;
  auto who = [&] { return "render pass '" + pass.name + "'"; };
  for (size_t i = 0; i < pass.attachments.size(); ++i) {
    const auto& a = pass.attachments[i];
    const std::string attachment = who() + ": attachment " + std::to_string(i);
    if (a.format == VK_FORMAT_UNDEFINED)
      return detail::failure(ErrorCode::corrupt, attachment + " has no format");
    if (a.final_layout == VK_IMAGE_LAYOUT_UNDEFINED || a.final_layout == VK_IMAGE_LAYOUT_PREINITIALIZED)
      return detail::failure(ErrorCode::corrupt, attachment + " has an invalid final layout");
    const bool depth = is_depth_format(a.format);
    for (uint32_t layout : {a.initial_layout, a.final_layout})
      if (depth ? layout == VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL
                : depth_layout(layout) && layout != VK_IMAGE_LAYOUT_GENERAL)
        return detail::failure(ErrorCode::corrupt,
                               attachment + "'s initial or final layout does not fit its format");
    const VkFormatFeatureFlags needed =
        depth ? VK_FORMAT_FEATURE_DEPTH_STENCIL_ATTACHMENT_BIT : VK_FORMAT_FEATURE_COLOR_ATTACHMENT_BIT;
    if (!supports(caps.format(a.format), needed))
      return detail::failure(ErrorCode::unsupported, attachment + ": the device cannot render to format " +
                                                         vk_name(VkFormat(a.format)));
    const VkSampleCountFlags counts = depth ? l.framebufferDepthSampleCounts : l.framebufferColorSampleCounts;
    if (!(counts & a.samples))
      return detail::failure(ErrorCode::unsupported, attachment + " has " + std::to_string(a.samples) +
                                                         " samples, which the device does not support");
  }
  // An attachment cleared on load must first be used in a layout that can be written.
  for (uint32_t i = 0; i < pass.attachments.size(); ++i) {
    const auto& a = pass.attachments[i];
    if (a.load_op != VK_ATTACHMENT_LOAD_OP_CLEAR && a.stencil_load_op != VK_ATTACHMENT_LOAD_OP_CLEAR)
      continue;
    for (const auto& sp : pass.subpasses) {
      std::optional<uint32_t> layout;
      for (const auto* list : {&sp.colors, &sp.resolves, &sp.inputs})
        for (const auto& r : *list)
          if (r.attachment == i && !layout) layout = r.layout;
      if (sp.depth_stencil.attachment == i && !layout) layout = sp.depth_stencil.layout;
      if (!layout) continue;
      if (read_only_layout(*layout))
        return detail::failure(ErrorCode::corrupt, who() + ": attachment " + std::to_string(i) +
                                                       " is cleared but first used in a read-only layout");
      break;
    }
  }
  for (size_t s = 0; s < pass.subpasses.size(); ++s) {
    const auto& sp = pass.subpasses[s];
    const std::string subpass = who() + ": subpass " + std::to_string(s);
    if (sp.colors.size() > l.maxColorAttachments)
      return over_limit(subpass, "the color attachment count", sp.colors.size(), "maxColorAttachments",
                        l.maxColorAttachments);
    if (sp.inputs.size() > l.maxPerStageDescriptorInputAttachments)
      return over_limit(subpass, "the input attachment count", sp.inputs.size(),
                        "maxPerStageDescriptorInputAttachments", l.maxPerStageDescriptorInputAttachments);
    uint32_t samples = 0;
    auto use = [&](const format::AttachmentRef& r, bool color) -> Result<void> {
      if (r.attachment == format::kNone) return {};
      const auto& a = pass.attachments[r.attachment];
      if (color ? (is_depth_format(a.format) || !color_layout(r.layout))
                : (!is_depth_format(a.format) || !depth_layout(r.layout)))
        return detail::failure(ErrorCode::corrupt, subpass + " uses attachment " +
                                                       std::to_string(r.attachment) + " as a " +
                                                       (color ? "color" : "depth") +
                                                       " attachment with a format or layout "
                                                       "that does not fit");
      if (samples != 0 && samples != a.samples)
        return detail::failure(ErrorCode::corrupt, subpass + " mixes attachments of different sample counts");
      samples = a.samples;
      return {};
    };
    for (const auto& r : sp.colors)
      if (auto ok = use(r, true); !ok) return ok;
    if (auto ok = use(sp.depth_stencil, false); !ok) return ok;
    for (const auto& r : sp.inputs)
      if (r.attachment != format::kNone && !input_layout(r.layout))
        return detail::failure(ErrorCode::corrupt, subpass + " reads input attachment " +
                                                       std::to_string(r.attachment) +
                                                       " in a layout that does not allow it");
    for (size_t i = 0; i < sp.resolves.size(); ++i) {
      const auto& r = sp.resolves[i];
      if (r.attachment == format::kNone) continue;
      const auto& color = sp.colors[i];
      if (color.attachment == format::kNone || pass.attachments[color.attachment].samples == 1 ||
          pass.attachments[r.attachment].samples != 1 ||
          pass.attachments[r.attachment].format != pass.attachments[color.attachment].format ||
          !color_layout(r.layout))
        return detail::failure(ErrorCode::corrupt, subpass + " resolves color attachment " +
                                                       std::to_string(i) +
                                                       " into an attachment that does not fit");
    }
    // Every use of one attachment within a subpass is in one layout (VUID-VkSubpassDescription-layout-02519).
    std::map<uint32_t, uint32_t> layout_of;
    for (const auto* list : {&sp.colors, &sp.inputs, &sp.resolves})
      for (const auto& r : *list) {
        if (r.attachment == format::kNone) continue;
        if (auto [it, first] = layout_of.emplace(r.attachment, r.layout); !first && it->second != r.layout)
          return detail::failure(
              ErrorCode::corrupt,
              subpass + " uses attachment " + std::to_string(r.attachment) + " in two different layouts");
      }
    if (sp.depth_stencil.attachment != format::kNone)
      if (auto it = layout_of.find(sp.depth_stencil.attachment);
          it != layout_of.end() && it->second != sp.depth_stencil.layout)
        return detail::failure(ErrorCode::corrupt, subpass + " uses attachment " +
                                                       std::to_string(sp.depth_stencil.attachment) +
                                                       " in two different layouts");
    for (uint32_t p : sp.preserve) {
      auto used = [&](const format::AttachmentRef& r) { return r.attachment == p; };
      if (p == format::kNone || std::any_of(sp.colors.begin(), sp.colors.end(), used) ||
          std::any_of(sp.inputs.begin(), sp.inputs.end(), used) ||
          std::any_of(sp.resolves.begin(), sp.resolves.end(), used) || used(sp.depth_stencil))
        return detail::failure(ErrorCode::corrupt, subpass + " preserves an attachment it uses");
    }
  }
  return {};
}

Result<void> check_sampler(const format::Sampler& s, const DeviceCaps& caps, std::string_view owner) {
  const VkPhysicalDeviceLimits& l = caps.properties.limits;
  auto who = [&] { return "immutable sampler of '" + std::string(owner) + "'"; };
  auto bad = [&](const char* why) { return detail::failure(ErrorCode::corrupt, who() + " " + why); };
  for (float f : {s.mip_lod_bias, s.max_anisotropy, s.min_lod, s.max_lod})
    if (!std::isfinite(f)) return bad("has a value that is not a finite number");
  if (std::fabs(s.mip_lod_bias) > l.maxSamplerLodBias) return bad("has a LOD bias beyond maxSamplerLodBias");
  if (s.anisotropy_enable && (s.max_anisotropy < 1 || s.max_anisotropy > l.maxSamplerAnisotropy))
    return bad("has an anisotropy beyond 1 to maxSamplerAnisotropy");
  if (s.min_lod > s.max_lod) return bad("has a minimum LOD above its maximum LOD");
  if (s.unnormalized_coordinates &&
      (s.min_filter != s.mag_filter || s.mipmap_mode != VK_SAMPLER_MIPMAP_MODE_NEAREST || s.min_lod != 0 ||
       s.max_lod != 0 || s.anisotropy_enable || s.compare_enable ||
       (s.address_u != VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE &&
        s.address_u != VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_BORDER) ||
       (s.address_v != VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE &&
        s.address_v != VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_BORDER)))
    return bad("uses unnormalized coordinates with filters, LODs or address modes they do not allow");
  return {};
}

Result<void> check_workgroup_size(const std::string& pipeline, const spirv::EntryPoint& entry,
                                  const std::function<std::optional<uint32_t>(uint32_t)>& specialized,
                                  const VkPhysicalDeviceLimits& limits) {
  if (!entry.workgroup_size) return {};  // none, or computed from constants: left to the driver
  const spirv::WorkgroupSize size = spirv::specialized_workgroup_size(*entry.workgroup_size, specialized);
  auto who = [&] { return "pipeline '" + pipeline + "'"; };
  auto text = [&] { return spirv::workgroup_size_text(size); };
  const auto& max = limits.maxComputeWorkGroupSize;
  for (size_t i = 0; i < 3; ++i) {
    if (size[i] == 0)
      return detail::failure(ErrorCode::invalid_argument, who() + ": the work-group size is " + text() +
                                                              "; each dimension must be at least 1");
    if (size[i] > max[i])
      return detail::failure(
          ErrorCode::unsupported,
          who() + ": the work-group size " + text() + " is beyond the device's maxComputeWorkGroupSize of (" +
              std::to_string(max[0]) + ", " + std::to_string(max[1]) + ", " + std::to_string(max[2]) + ")");
  }
  const uint64_t invocations = size[0] * size[1] * size[2];
  if (invocations > limits.maxComputeWorkGroupInvocations)
    return detail::failure(ErrorCode::unsupported,
                           who() + ": a work group of " + text() + " is " + std::to_string(invocations) +
                               " invocations, beyond the device's maxComputeWorkGroupInvocations of " +
                               std::to_string(limits.maxComputeWorkGroupInvocations));
  return {};
}

Result<void> check_pipeline_layout(const format::Contents& c, const format::Pipeline& p,
                                   const DeviceCaps& caps) {
  const VkPhysicalDeviceLimits& l = caps.properties.limits;
  auto who = [&] { return "pipeline '" + p.name + "'"; };
  for (uint32_t s : p.shaders) {
    const auto& words = c.spirv[c.shaders[s].blob];  // the header was checked at load time
    const uint32_t needed = api_version_for_spirv(words[1]);
    if (caps.properties.apiVersion < needed)
      return detail::failure(ErrorCode::unsupported, who() + ": shader '" + c.shaders[s].name +
                                                         "' is SPIR-V " + std::to_string(words[1] >> 16) +
                                                         "." + std::to_string((words[1] >> 8) & 0xFF) +
                                                         ", which needs a newer Vulkan than the device's");
  }
  if (p.set_layouts.size() > l.maxBoundDescriptorSets)
    return over_limit(who(), "the descriptor set count", p.set_layouts.size(), "maxBoundDescriptorSets",
                      l.maxBoundDescriptorSets);
  DescriptorTotals layout_totals;
  std::array<DescriptorTotals, 6> stage_totals;
  uint32_t stages_used = 0;
  for (uint32_t index : p.set_layouts) {
    if (index == format::kNone) continue;
    for (const auto& b : c.set_layouts[index].bindings) {
      layout_totals.add(b.descriptor_type, b.count);
      stages_used |= b.stage_flags;
      for (uint32_t stage = 0; stage < stage_totals.size(); ++stage)
        if (b.stage_flags & (1u << stage)) stage_totals[stage].add(b.descriptor_type, b.count);
    }
  }
  if (auto ok = check_layout_totals(layout_totals, l, who); !ok) return ok;
  for (uint32_t stage = 0; stage < stage_totals.size(); ++stage)  // (the message only for a stage in use)
    if (stages_used & (1u << stage))
      if (auto ok =
              check_stage_totals(stage_totals[stage], l,
                                 [&] { return who() + " (" + spirv::stage_name(1u << stage) + " stage)"; });
          !ok)
        return ok;
  if (p.push_constant_size > l.maxPushConstantsSize)
    return over_limit(who(), "the push constant size", p.push_constant_size, "maxPushConstantsSize",
                      l.maxPushConstantsSize);
  if (p.push_constant_size > 0 && p.push_constant_stages == 0)
    return detail::failure(ErrorCode::corrupt, who() + " has " + std::to_string(p.push_constant_size) +
                                                   " bytes of push constants for no shader stage");
  return {};
}

namespace {

Result<void> check_vertex_input(const format::GraphicsState& g, Lazy who, const DeviceCaps& caps) {
  const VkPhysicalDeviceLimits& l = caps.properties.limits;
  if (g.vertex_bindings.size() > l.maxVertexInputBindings)
    return over_limit(who(), "the vertex binding count", g.vertex_bindings.size(), "maxVertexInputBindings",
                      l.maxVertexInputBindings);
  for (size_t i = 0; i < g.vertex_bindings.size(); ++i) {
    const auto& b = g.vertex_bindings[i];
    auto binding = [&] { return "vertex binding " + std::to_string(b.binding); };
    if (b.binding >= l.maxVertexInputBindings)
      return over_limit(who(), "a vertex binding number", b.binding, "maxVertexInputBindings",
                        l.maxVertexInputBindings);
    if (b.stride > l.maxVertexInputBindingStride)
      return over_limit(who(), "the stride of " + binding(), b.stride, "maxVertexInputBindingStride",
                        l.maxVertexInputBindingStride);
    for (size_t j = 0; j < i; ++j)
      if (g.vertex_bindings[j].binding == b.binding)
        return detail::failure(ErrorCode::corrupt, who() + " declares " + binding() + " twice");
  }
  if (g.vertex_attributes.size() > l.maxVertexInputAttributes)
    return over_limit(who(), "the vertex attribute count", g.vertex_attributes.size(),
                      "maxVertexInputAttributes", l.maxVertexInputAttributes);
  for (size_t i = 0; i < g.vertex_attributes.size(); ++i) {
    const auto& a = g.vertex_attributes[i];
    auto attribute = [&] { return "vertex attribute at location " + std::to_string(a.location); };
    if (a.location >= l.maxVertexInputAttributes)
      return over_limit(who(), "a vertex attribute location", a.location, "maxVertexInputAttributes",
                        l.maxVertexInputAttributes);
    if (a.offset > l.maxVertexInputAttributeOffset)
      return over_limit(who(), "the offset of the " + attribute(), a.offset, "maxVertexInputAttributeOffset",
                        l.maxVertexInputAttributeOffset);
    for (size_t j = 0; j < i; ++j)
      if (g.vertex_attributes[j].location == a.location)
        return detail::failure(ErrorCode::corrupt, who() + " declares the " + attribute() + " twice");
    if (!(caps.format(a.format).bufferFeatures & VK_FORMAT_FEATURE_VERTEX_BUFFER_BIT))
      return detail::failure(ErrorCode::unsupported, who() + ": the " + attribute() + " has format " +
                                                         vk_name(VkFormat(a.format)) +
                                                         ", which the device cannot read vertices from");
  }
  return {};
}

// Without a render pass the pipeline's own formats are the attachments: the device must render to them.
Result<void> check_dynamic_rendering_targets(const GraphicsTargets& t, Lazy who, const DeviceCaps& caps) {
  const VkPhysicalDeviceLimits& l = caps.properties.limits;
  for (uint32_t i = 0; i < t.color_count; ++i) {
    if (t.color_formats[i] == VK_FORMAT_UNDEFINED) continue;
    const VkFormatProperties f = caps.format(t.color_formats[i]);
    if (!supports(f, VK_FORMAT_FEATURE_COLOR_ATTACHMENT_BIT))
      return detail::failure(ErrorCode::unsupported, who() + ": render target " + std::to_string(i) +
                                                         " has format " +
                                                         vk_name(VkFormat(t.color_formats[i])) +
                                                         ", which the device cannot render to");
    if (t.blend_enabled[i] && !supports(f, VK_FORMAT_FEATURE_COLOR_ATTACHMENT_BLEND_BIT))
      return detail::failure(ErrorCode::unsupported,
                             who() + ": render target " + std::to_string(i) + " blends format " +
                                 vk_name(VkFormat(t.color_formats[i])) + ", which the device cannot blend");
  }
  if (t.depth_stencil_format != VK_FORMAT_UNDEFINED &&
      !supports(caps.format(t.depth_stencil_format), VK_FORMAT_FEATURE_DEPTH_STENCIL_ATTACHMENT_BIT))
    return detail::failure(ErrorCode::unsupported, who() + ": depth-stencil format " +
                                                       vk_name(VkFormat(t.depth_stencil_format)) +
                                                       " cannot be rendered to on this device");
  if (t.depth_stencil_format != VK_FORMAT_UNDEFINED && !(l.framebufferDepthSampleCounts & t.samples))
    return detail::failure(ErrorCode::unsupported, who() + " renders depth with " +
                                                       std::to_string(t.samples) +
                                                       " samples, which the device does not support");
  return {};
}

// The render pass fixes the attachments: the pipeline must agree with its subpass.
Result<void> check_subpass_targets(const format::Contents& c, const format::Pipeline& p,
                                   const GraphicsTargets& t, Lazy who, const DeviceCaps& caps) {
  const format::RenderPass& pass = c.render_passes[p.render_pass];
  const format::Subpass& sp = pass.subpasses[p.subpass];
  if (t.color_count != sp.colors.size())
    return detail::failure(ErrorCode::corrupt, who() + " blends " + std::to_string(t.color_count) +
                                                   " render target(s), but its subpass " +
                                                   std::to_string(p.subpass) + " of render pass '" +
                                                   pass.name + "' has " + std::to_string(sp.colors.size()));
  std::vector<format::AttachmentRef> used(sp.colors.begin(), sp.colors.end());
  used.push_back(sp.depth_stencil);
  for (const auto& r : used)
    if (r.attachment != format::kNone && pass.attachments[r.attachment].samples != t.samples)
      return detail::failure(ErrorCode::corrupt, who() + " renders with " + std::to_string(t.samples) +
                                                     " samples, but attachment " +
                                                     std::to_string(r.attachment) + " of render pass '" +
                                                     pass.name + "' has " +
                                                     std::to_string(pass.attachments[r.attachment].samples));
  for (uint32_t i = 0; i < t.color_count; ++i)
    if (t.blend_enabled[i] && sp.colors[i].attachment != format::kNone &&
        !supports(caps.format(pass.attachments[sp.colors[i].attachment].format),
                  VK_FORMAT_FEATURE_COLOR_ATTACHMENT_BLEND_BIT))
      return detail::failure(ErrorCode::unsupported, who() + ": render target " + std::to_string(i) +
                                                         " blends a format the device cannot blend");
  return {};
}

// Points need a PointSize from the last stage before rasterization (here only the vertex stage can
// be: geometry and tessellation shaders leave it to their own output).
Result<void> check_point_size(const format::Contents& c, const format::Pipeline& p, Lazy who,
                              const ModuleOf& module_of) {
  uint32_t stages = 0;
  for (uint32_t index : p.shaders) stages |= c.shaders[index].stage;
  if (p.graphics.topology != VK_PRIMITIVE_TOPOLOGY_POINT_LIST ||
      (stages & (VK_SHADER_STAGE_GEOMETRY_BIT | VK_SHADER_STAGE_TESSELLATION_EVALUATION_BIT)))
    return {};
  for (uint32_t index : p.shaders) {
    const format::Shader& shader = c.shaders[index];
    if (shader.stage != VK_SHADER_STAGE_VERTEX_BIT) continue;
    const spirv::Module* module = module_of(shader.blob);
    if (!module)
      return detail::failure(ErrorCode::corrupt, "shader '" + shader.name + "' has no readable SPIR-V");
    if (!module->writes_point_size)
      return detail::failure(ErrorCode::corrupt, who() + " draws points, but its vertex shader '" +
                                                     shader.name + "' does not write PointSize");
  }
  return {};
}

// Vertex inputs and fragment outputs against the formats they meet.
Result<void> check_interface_formats(const format::Contents& c, const format::Pipeline& p,
                                     const GraphicsTargets& t, Lazy who, const ModuleOf& module_of) {
  for (uint32_t index : p.shaders) {
    const format::Shader& shader = c.shaders[index];
    if (shader.stage != VK_SHADER_STAGE_VERTEX_BIT && shader.stage != VK_SHADER_STAGE_FRAGMENT_BIT) continue;
    const spirv::Module* module = module_of(shader.blob);
    if (!module)
      return detail::failure(ErrorCode::corrupt, "shader '" + shader.name + "' has no readable SPIR-V");
    if (shader.stage == VK_SHADER_STAGE_VERTEX_BIT) {
      for (const auto& a : p.graphics.vertex_attributes)
        if (auto ok = check_numeric(
                module->inputs, a.location, a.format,
                [&] { return who() + ": the vertex attribute at location " + std::to_string(a.location); });
            !ok)
          return ok;
    } else if (p.render_pass == format::kNone) {
      for (uint32_t i = 0; i < t.color_count; ++i)
        if (auto ok = check_numeric(
                module->outputs, i, t.color_formats[i],
                [&] { return who() + ": render target " + std::to_string(i); },
                (t.patched_targets >> i) & 1u);
            !ok)
          return ok;
    } else {
      const format::RenderPass& pass = c.render_passes[p.render_pass];
      const format::Subpass& sp = pass.subpasses[p.subpass];
      for (uint32_t i = 0; i < sp.colors.size(); ++i)
        if (sp.colors[i].attachment != format::kNone)
          if (auto ok = check_numeric(module->outputs, i, pass.attachments[sp.colors[i].attachment].format,
                                      [&] { return who() + ": render target " + std::to_string(i); });
              !ok)
            return ok;
    }
  }
  return {};
}

}  // namespace

Result<void> check_graphics_state(const format::Contents& c, const format::Pipeline& p,
                                  const GraphicsTargets& t, const DeviceCaps& caps,
                                  const ModuleOf& module_of) {
  const VkPhysicalDeviceLimits& l = caps.properties.limits;
  auto who = [&] { return "pipeline '" + p.name + "'"; };
  if (auto ok = check_vertex_input(p.graphics, who, caps); !ok) return ok;
  if (t.color_count > l.maxColorAttachments)
    return over_limit(who(), "the color attachment count", t.color_count, "maxColorAttachments",
                      l.maxColorAttachments);
  const bool dynamic_rendering = p.render_pass == format::kNone;
  if (auto ok = dynamic_rendering ? check_dynamic_rendering_targets(t, who, caps)
                                  : check_subpass_targets(c, p, t, who, caps);
      !ok)
    return ok;
  if (auto ok = check_point_size(c, p, who, module_of); !ok) return ok;
  return check_interface_formats(c, p, t, who, module_of);
}

}  // namespace statepack::detail
