#include "patchable_state.hpp"

#include "support/failure.hpp"

#include "vk_enum_names.hpp"

#include <bit>
#include <string_view>
#include <unordered_map>

namespace statepack::detail {

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
  return vk_name(state);
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
  s.dynamic_states.reserve(size_t(std::popcount(p.dynamic_states)));  // one allocation, not one per growth
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

Result<std::vector<SpecializationConstant>> settle_constants(const format::Pipeline& p,
                                                             std::vector<SpecializationConstant> given) {
  std::vector<SpecializationConstant> archived = constants_of(p);
  if (given.empty()) return archived;  // none given, or all removed: the archived values
  std::unordered_map<std::string_view, size_t> index;
  for (size_t i = 0; i < archived.size(); ++i) index.emplace(archived[i].name, i);
  for (const auto& g : given) {
    auto it = index.find(g.name);
    if (it == index.end())
      return detail::failure(ErrorCode::invalid_argument, "pipeline '" + p.name +
                                                              "' has no specialization constant '" + g.name +
                                                              "' (the modify callback added it)");
    SpecializationConstant& a = archived[it->second];
    if (g.size != a.size)
      return detail::failure(ErrorCode::invalid_argument,
                             "pipeline '" + p.name + "': specialization constant '" + g.name + "' is " +
                                 std::to_string(a.size) + " bytes, but the modify callback gave " +
                                 std::to_string(g.size));
    a.value = g.value;  // a constant the callback removed keeps the archived value
  }
  return archived;
}

}  // namespace statepack::detail
