// Vulkan developers type Vulkan's names: `VK_FORMAT_R16G16B16A16_SFLOAT`, `ONE_MINUS_SRC_ALPHA`,
// `FRAGMENT`. For the notation's tables whose values are Vulkan enums, this finds the notation's name
// for such a spelling (`RGBA16_FLOAT`, `INV_SRC_ALPHA`, `PIXEL`), using Vulkan's own names of the values
// (vulkan.hpp's to_string) as the one mapping table, so it cannot drift from the values.
#pragma once

#include <optional>
#include <string_view>

#include "enum_tables.hpp"

namespace statepack::packager {

// The notation's name for `text` when `text` is Vulkan's name (with or without its VK_..._ prefix,
// any case) of a value of `table`; nullopt otherwise, and for tables that are not Vulkan enums.
std::optional<std::string_view> notation_name_for_vulkan_spelling(EnumTable table, std::string_view text);

}  // namespace statepack::packager
