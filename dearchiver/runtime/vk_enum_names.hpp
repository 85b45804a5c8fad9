// Vulkan's own names for the enum values runtime messages show ("VK_FORMAT_D32_SFLOAT", not 126),
// from tables generated at build time from vk.xml (vk_enum_names_gen.py). A value Vulkan does not
// define is shown as its type and number ("VkFormat 2147418112").
#pragma once

#include <vulkan/vulkan_core.h>

#include <string>
#include <string_view>
#include <vector>

namespace statepack::detail {

std::string vk_name(VkFormat value);
std::string vk_name(VkDynamicState value);
std::string vk_name(VkBlendFactor value);
std::string vk_name(VkBlendOp value);
std::string vk_name(VkCompareOp value);
std::string vk_name(VkStencilOp value);
std::string vk_name(VkPolygonMode value);
std::string vk_name(VkFrontFace value);
std::string vk_name(VkPrimitiveTopology value);
std::string vk_name(VkSampleCountFlagBits value);
std::string vk_name(VkDescriptorType value);
std::string vk_name(VkLogicOp value);

// The value of a Vulkan name ("VK_FORMAT_B8G8R8A8_SRGB"), as vk_name spells it; false for a name the
// type does not have.
bool vk_value(std::string_view name, VkFormat& out);
bool vk_value(std::string_view name, VkDynamicState& out);
bool vk_value(std::string_view name, VkBlendFactor& out);
bool vk_value(std::string_view name, VkBlendOp& out);
bool vk_value(std::string_view name, VkCompareOp& out);
bool vk_value(std::string_view name, VkStencilOp& out);
bool vk_value(std::string_view name, VkPolygonMode& out);
bool vk_value(std::string_view name, VkFrontFace& out);
bool vk_value(std::string_view name, VkSampleCountFlagBits& out);

// Every name of the type (the argument only picks it), for "did you mean" on a name vk_value refused.
std::vector<std::string> vk_names(VkFormat);
std::vector<std::string> vk_names(VkDynamicState);
std::vector<std::string> vk_names(VkBlendFactor);
std::vector<std::string> vk_names(VkBlendOp);
std::vector<std::string> vk_names(VkCompareOp);
std::vector<std::string> vk_names(VkStencilOp);
std::vector<std::string> vk_names(VkPolygonMode);
std::vector<std::string> vk_names(VkFrontFace);
std::vector<std::string> vk_names(VkSampleCountFlagBits);

// Depth, stencil or both: a format that can only be a depth-stencil attachment.
bool is_depth_stencil_format(VkFormat format);

}  // namespace statepack::detail
