#include "vk_enum_names.hpp"

#include <algorithm>
#include <cstdint>
#include <iterator>

namespace statepack::detail {
namespace {

struct EnumName {
  int64_t value;
  const char* name;
};

#include "vk_enum_names.inc"

template <size_t N>
std::string lookup(const EnumName (&table)[N], int64_t value, const char* type) {
  const EnumName* it = std::lower_bound(std::begin(table), std::end(table), value,
                                        [](const EnumName& e, int64_t v) { return e.value < v; });
  if (it != std::end(table) && it->value == value) return it->name;
  return std::string(type) + " " + std::to_string(value);
}

}  // namespace

std::string vk_name(VkFormat value) {
  return lookup(kVkFormatNames, value, "VkFormat");
}
std::string vk_name(VkDynamicState value) {
  return lookup(kVkDynamicStateNames, value, "VkDynamicState");
}
std::string vk_name(VkBlendFactor value) {
  return lookup(kVkBlendFactorNames, value, "VkBlendFactor");
}
std::string vk_name(VkBlendOp value) {
  return lookup(kVkBlendOpNames, value, "VkBlendOp");
}
std::string vk_name(VkCompareOp value) {
  return lookup(kVkCompareOpNames, value, "VkCompareOp");
}
std::string vk_name(VkStencilOp value) {
  return lookup(kVkStencilOpNames, value, "VkStencilOp");
}
std::string vk_name(VkPolygonMode value) {
  return lookup(kVkPolygonModeNames, value, "VkPolygonMode");
}
std::string vk_name(VkFrontFace value) {
  return lookup(kVkFrontFaceNames, value, "VkFrontFace");
}
std::string vk_name(VkPrimitiveTopology value) {
  return lookup(kVkPrimitiveTopologyNames, value, "VkPrimitiveTopology");
}
std::string vk_name(VkSampleCountFlagBits value) {
  return lookup(kVkSampleCountFlagBitsNames, value, "VkSampleCountFlagBits");
}
std::string vk_name(VkDescriptorType value) {
  return lookup(kVkDescriptorTypeNames, value, "VkDescriptorType");
}
std::string vk_name(VkLogicOp value) {
  return lookup(kVkLogicOpNames, value, "VkLogicOp");
}

bool is_depth_stencil_format(VkFormat format) {
  return format >= VK_FORMAT_D16_UNORM && format <= VK_FORMAT_D32_SFLOAT_S8_UINT;
}

}  // namespace statepack::detail
