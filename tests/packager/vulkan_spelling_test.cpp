// Vulkan's spellings of the notation's values get the notation's name as the suggestion, for every value
// of every table whose values are Vulkan enums (the mapping is Vulkan's own names: it cannot drift).
#include <gtest/gtest.h>

#include <vulkan/vulkan.hpp>

#include "notation/vulkan_spelling.hpp"

namespace statepack::packager {
namespace {

TEST(VulkanSpelling, TheIssuesExamples) {
  EXPECT_EQ(notation_name_for_vulkan_spelling(kTextureFormats, "R16G16B16A16_SFLOAT"), "RGBA16_FLOAT");
  EXPECT_EQ(notation_name_for_vulkan_spelling(kTextureFormats, "VK_FORMAT_R16G16B16A16_SFLOAT"),
            "RGBA16_FLOAT");
  EXPECT_EQ(notation_name_for_vulkan_spelling(kBlendFactors, "ONE_MINUS_SRC_ALPHA"), "INV_SRC_ALPHA");
  EXPECT_EQ(notation_name_for_vulkan_spelling(kShaderTypes, "FRAGMENT"), "PIXEL");
  EXPECT_EQ(notation_name_for_vulkan_spelling(kComparisonFuncs, "VK_COMPARE_OP_LESS_OR_EQUAL"), "LESS_EQUAL");
  EXPECT_EQ(notation_name_for_vulkan_spelling(kCullModes, "VK_CULL_MODE_FRONT_BIT"), "FRONT");
  // Issue 24: filters and dynamic states by Vulkan's names (POINT is VK_FILTER_NEAREST).
  EXPECT_EQ(notation_name_for_vulkan_spelling(kFilterTypes, "VK_FILTER_NEAREST"), "POINT");
  EXPECT_EQ(notation_name_for_vulkan_spelling(kFilterTypes, "VK_FILTER_LINEAR"), "LINEAR");
  EXPECT_EQ(notation_name_for_vulkan_spelling(kDynamicStates, "VK_DYNAMIC_STATE_VIEWPORT"), "VIEWPORT");
  EXPECT_EQ(notation_name_for_vulkan_spelling(kDynamicStates, "VK_DYNAMIC_STATE_STENCIL_REFERENCE"),
            "STENCIL_REFERENCE");
  EXPECT_FALSE(notation_name_for_vulkan_spelling(kFilterTypes, "VK_FILTER_CUBIC_EXT"));
  // Not Vulkan's name of anything in the table, or a table that is not a Vulkan enum: no suggestion.
  EXPECT_FALSE(notation_name_for_vulkan_spelling(kTextureFormats, "FRAGMENT"));
  EXPECT_FALSE(notation_name_for_vulkan_spelling(kVariableTypes, "STATIC"));
}

TEST(VulkanSpelling, EveryFormatOfTheNotationMapsBackFromVulkansName) {
  size_t checked = 0;
  for (const auto& [name, value] : kTextureFormats) {
    if (value == kUnsupportedValue || value == VK_FORMAT_UNDEFINED) continue;
    const std::string vulkan =
        "VK_FORMAT_" + vk::to_string(vk::Format(value));  // e.g. VK_FORMAT_R8G8B8A8Unorm
    EXPECT_EQ(notation_name_for_vulkan_spelling(kTextureFormats, vulkan), name) << vulkan;
    ++checked;
  }
  EXPECT_GT(checked, 40u);
}

}  // namespace
}  // namespace statepack::packager
