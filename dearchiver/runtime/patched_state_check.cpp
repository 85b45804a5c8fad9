#include "patched_state_check.hpp"

#include "support/failure.hpp"

#include "vk_enum_names.hpp"

#include <bit>
#include <cmath>
#include <string>

namespace statepack::detail {
namespace {

struct Checker {
  std::string_view pipeline;
  std::optional<Error> error;

  // Records the first bad value; `field` as the application spells it.
  [[gnu::cold]] void fail(const std::string& field, int64_t value, const char* what) {
    if (error) return;
    error = detail::failure(ErrorCode::invalid_argument,
                            "pipeline '" + std::string(pipeline) +
                                "': the modify callback set PatchableState::" + field + " to " +
                                std::to_string(value) + ", which is not " + what);
  }
  void finite(const std::string& field, float value) {
    if (error || std::isfinite(value)) return;
    error = detail::failure(ErrorCode::invalid_argument,
                            "pipeline '" + std::string(pipeline) +
                                "': the modify callback set PatchableState::" + field + " to " +
                                (std::isnan(value) ? "nan"
                                 : value < 0       ? "-inf"
                                                   : "inf") +
                                ", which is not a finite number");
  }
  void range(const std::string& field, int64_t value, int64_t last, const char* what) {
    if (value < 0 || value > last) fail(field, value, what);
  }
  void format(const std::string& field, VkFormat value) {
    range(field, value, VK_FORMAT_ASTC_12x12_SRGB_BLOCK, "a Vulkan 1.0 format");
  }
  // A valid format in the wrong kind of slot: Vulkan forbids it on every device, so it is the
  // caller's mistake (invalid_argument), not the device's limitation.
  void color_format(const std::string& field, VkFormat value) {
    format(field, value);
    if (error || !is_depth_stencil_format(value)) return;
    error = detail::failure(
        ErrorCode::invalid_argument,
        "pipeline '" + std::string(pipeline) + "': the modify callback set PatchableState::" + field +
            " to " + vk_name(value) + ", a depth-stencil format, which cannot be a colour render target");
  }
  void depth_format(const std::string& field, VkFormat value) {
    format(field, value);
    if (error || value == VK_FORMAT_UNDEFINED || is_depth_stencil_format(value)) return;
    error = detail::failure(ErrorCode::invalid_argument,
                            "pipeline '" + std::string(pipeline) +
                                "': the modify callback set PatchableState::" + field + " to " +
                                vk_name(value) + ", which has no depth or stencil component");
  }
  void compare(const std::string& field, VkCompareOp value) {
    range(field, value, VK_COMPARE_OP_ALWAYS, "a VkCompareOp");
  }
  void stencil(const std::string& face, const VkStencilOpState& s) {
    range("depth_stencil." + face + ".failOp", s.failOp, VK_STENCIL_OP_DECREMENT_AND_WRAP, "a VkStencilOp");
    range("depth_stencil." + face + ".passOp", s.passOp, VK_STENCIL_OP_DECREMENT_AND_WRAP, "a VkStencilOp");
    range("depth_stencil." + face + ".depthFailOp", s.depthFailOp, VK_STENCIL_OP_DECREMENT_AND_WRAP,
          "a VkStencilOp");
    compare("depth_stencil." + face + ".compareOp", s.compareOp);
  }
};

}  // namespace

std::optional<Error> check_patched_state(std::string_view pipeline, const PatchableState& s) {
  Checker c{pipeline, std::nullopt};
  c.range("color_count", s.color_count, int64_t(s.color_formats.size()), "8 or fewer");
  if (c.error) return c.error;
  for (uint32_t i = 0; i < s.color_count; ++i) {
    const std::string target = "[" + std::to_string(i) + "]";
    c.color_format("color_formats" + target, s.color_formats[i]);
    const BlendAttachmentState& b = s.blend[i];
    constexpr int64_t kLastFactor = VK_BLEND_FACTOR_ONE_MINUS_SRC1_ALPHA;
    c.range("blend" + target + ".src_color", b.src_color, kLastFactor, "a VkBlendFactor");
    c.range("blend" + target + ".dst_color", b.dst_color, kLastFactor, "a VkBlendFactor");
    c.range("blend" + target + ".src_alpha", b.src_alpha, kLastFactor, "a VkBlendFactor");
    c.range("blend" + target + ".dst_alpha", b.dst_alpha, kLastFactor, "a VkBlendFactor");
    c.range("blend" + target + ".color_op", b.color_op, VK_BLEND_OP_MAX, "a Vulkan 1.0 VkBlendOp");
    c.range("blend" + target + ".alpha_op", b.alpha_op, VK_BLEND_OP_MAX, "a Vulkan 1.0 VkBlendOp");
    c.range("blend" + target + ".write_mask", b.write_mask, 0xF, "a mask of R, G, B and A");
  }
  c.depth_format("depth_stencil_format", s.depth_stencil_format);
  if (!std::has_single_bit(uint32_t(s.samples)) || s.samples > VK_SAMPLE_COUNT_64_BIT)
    c.fail("samples", s.samples, "one VkSampleCountFlagBits");
  c.range("rasterizer.polygon_mode", s.rasterizer.polygon_mode, VK_POLYGON_MODE_POINT, "a VkPolygonMode");
  c.range("rasterizer.cull_mode", s.rasterizer.cull_mode, VK_CULL_MODE_FRONT_AND_BACK, "a VkCullModeFlags");
  c.range("rasterizer.front_face", s.rasterizer.front_face, VK_FRONT_FACE_CLOCKWISE, "a VkFrontFace");
  c.finite("rasterizer.depth_bias", s.rasterizer.depth_bias);
  c.finite("rasterizer.depth_bias_clamp", s.rasterizer.depth_bias_clamp);
  c.finite("rasterizer.depth_bias_slope", s.rasterizer.depth_bias_slope);
  c.compare("depth_stencil.depth_compare", s.depth_stencil.depth_compare);
  c.stencil("front", s.depth_stencil.front);
  c.stencil("back", s.depth_stencil.back);
  return c.error;
}

}  // namespace statepack::detail
