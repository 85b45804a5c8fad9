#include "variant_key.hpp"

#include <algorithm>
#include <cstring>
#include <type_traits>
#include <vector>

namespace statepack::detail {
namespace {

class KeyWriter {
 public:
  template <class T>
  void put(const T& value) {
    static_assert(std::is_arithmetic_v<T> || std::is_enum_v<T>);
    char bytes[sizeof(T)];
    std::memcpy(bytes, &value, sizeof(T));
    key.append(bytes, sizeof(T));
  }
  void put(std::string_view text) {
    put(uint64_t(text.size()));
    key.append(text);
  }
  void put(const VkStencilOpState& s) {
    for (uint32_t v : {uint32_t(s.failOp), uint32_t(s.passOp), uint32_t(s.depthFailOp), uint32_t(s.compareOp),
                       s.compareMask, s.writeMask, s.reference})
      put(v);
  }
  std::string key;
};

}  // namespace

std::string variant_key(std::string_view pipeline, const Plan& plan) {
  KeyWriter w;
  w.put(pipeline);
  w.put(plan.out.bind_point);
  // Specialization constants as the stages receive them (compute pipelines have only these).
  for (const Plan::StageConstants& sc : plan.constants) {
    w.put(uint64_t(sc.entries.size()));
    for (const VkSpecializationMapEntry& e : sc.entries) w.put(e.constantID);
    w.put(std::string_view(reinterpret_cast<const char*>(sc.data.data()), sc.data.size()));
  }
  if (plan.out.bind_point != VK_PIPELINE_BIND_POINT_GRAPHICS) return std::move(w.key);
  const PatchableState& s = plan.state;
  w.put(s.color_count);
  for (uint32_t i = 0; i < s.color_count && i < s.color_formats.size(); ++i) {
    w.put(s.color_formats[i]);
    const BlendAttachmentState& b = s.blend[i];
    w.put(b.enable);
    for (uint32_t v : {uint32_t(b.src_color), uint32_t(b.dst_color), uint32_t(b.color_op),
                       uint32_t(b.src_alpha), uint32_t(b.dst_alpha), uint32_t(b.alpha_op), b.write_mask})
      w.put(v);
  }
  w.put(s.depth_stencil_format);
  w.put(s.samples);
  const RasterizerState& r = s.rasterizer;
  w.put(r.polygon_mode);
  w.put(r.cull_mode);
  w.put(r.front_face);
  w.put(r.depth_clamp);
  for (float f : {r.depth_bias, r.depth_bias_clamp, r.depth_bias_slope}) w.put(f);
  const DepthStencilState& d = s.depth_stencil;
  w.put(d.depth_test);
  w.put(d.depth_write);
  w.put(d.depth_compare);
  w.put(d.stencil_test);
  w.put(d.front);
  w.put(d.back);
  std::vector<VkDynamicState> dynamic = s.dynamic_states;  // a set: the order means nothing to Vulkan
  std::sort(dynamic.begin(), dynamic.end());
  dynamic.erase(std::unique(dynamic.begin(), dynamic.end()), dynamic.end());
  w.put(uint64_t(dynamic.size()));
  for (VkDynamicState state : dynamic) w.put(state);
  return std::move(w.key);
}

}  // namespace statepack::detail
