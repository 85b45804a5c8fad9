// How `statepack inspect` spells the values of an archive (docs/cli.md, "Spellings"): as the notation
// spells them (RGBA16_FLOAT, TRIANGLE_LIST, SRC_ALPHA, PIXEL), so that what a notation author wrote and
// what inspect shows read alike; a value the notation has no name for as Vulkan spells it
// (VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_FORMAT_A2B10G10R10_UNORM_PACK32). Formats also carry Vulkan's
// name (vulkan_format_name, layout/format_support.hpp), which the runtime's messages and variants files use.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include "layout/format_support.hpp"  // format_name, vulkan_format_name, vulkan_upper_name
#include "notation/enum_tables.hpp"

namespace statepack::packager {

// The notation's name of `value` in `table` (its first, canonical name), else `vulkan`.
std::string notation_name(EnumTable table, uint32_t value, const std::string& vulkan);

// A bit mask as the notation's flag names joined by " | " ("NONE" for 0); a bit the table does not
// name is written as Vulkan's name of it (`vulkan_bit`).
template <class VulkanBit>
std::string notation_flags(EnumTable table, uint32_t flags, VulkanBit vulkan_bit) {
  if (flags == 0) return "NONE";
  std::string out;
  for (uint32_t bit = 1; bit != 0; bit <<= 1)
    if (flags & bit) out += (out.empty() ? "" : " | ") + notation_name(table, bit, vulkan_bit(bit));
  return out;
}

}  // namespace statepack::packager
