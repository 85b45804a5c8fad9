#include "vk_enum_names.hpp"

#include <algorithm>
#include <cstdint>
#include <iterator>
#include <string_view>

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

namespace {

// The value Vulkan names `name` in `table`: a linear scan, for the few names a variants file holds.
template <class E, size_t N>
bool find_value(const EnumName (&table)[N], std::string_view name, E& out) {
  for (const EnumName& e : table)
    if (name == e.name) {
      out = static_cast<E>(e.value);
      return true;
    }
  return false;
}

}  // namespace

bool vk_value(std::string_view name, VkFormat& out) {
  return find_value(kVkFormatNames, name, out);
}
bool vk_value(std::string_view name, VkDynamicState& out) {
  return find_value(kVkDynamicStateNames, name, out);
}
bool vk_value(std::string_view name, VkBlendFactor& out) {
  return find_value(kVkBlendFactorNames, name, out);
}
bool vk_value(std::string_view name, VkBlendOp& out) {
  return find_value(kVkBlendOpNames, name, out);
}
bool vk_value(std::string_view name, VkCompareOp& out) {
  return find_value(kVkCompareOpNames, name, out);
}
bool vk_value(std::string_view name, VkStencilOp& out) {
  return find_value(kVkStencilOpNames, name, out);
}
bool vk_value(std::string_view name, VkPolygonMode& out) {
  return find_value(kVkPolygonModeNames, name, out);
}
bool vk_value(std::string_view name, VkFrontFace& out) {
  return find_value(kVkFrontFaceNames, name, out);
}
bool vk_value(std::string_view name, VkSampleCountFlagBits& out) {
  return find_value(kVkSampleCountFlagBitsNames, name, out);
}

namespace {

template <size_t N>
std::vector<std::string> names_of(const EnumName (&table)[N]) {
  std::vector<std::string> out;
  out.reserve(N);
  for (const EnumName& e : table) out.emplace_back(e.name);
  return out;
}

}  // namespace

std::vector<std::string> vk_names(VkFormat) {
  return names_of(kVkFormatNames);
}
std::vector<std::string> vk_names(VkDynamicState) {
  return names_of(kVkDynamicStateNames);
}
std::vector<std::string> vk_names(VkBlendFactor) {
  return names_of(kVkBlendFactorNames);
}
std::vector<std::string> vk_names(VkBlendOp) {
  return names_of(kVkBlendOpNames);
}
std::vector<std::string> vk_names(VkCompareOp) {
  return names_of(kVkCompareOpNames);
}
std::vector<std::string> vk_names(VkStencilOp) {
  return names_of(kVkStencilOpNames);
}
std::vector<std::string> vk_names(VkPolygonMode) {
  return names_of(kVkPolygonModeNames);
}
std::vector<std::string> vk_names(VkFrontFace) {
  return names_of(kVkFrontFaceNames);
}
std::vector<std::string> vk_names(VkSampleCountFlagBits) {
  return names_of(kVkSampleCountFlagBitsNames);
}

bool is_depth_stencil_format(VkFormat format) {
  return format >= VK_FORMAT_D16_UNORM && format <= VK_FORMAT_D32_SFLOAT_S8_UINT;
}

}  // namespace statepack::detail
