// What a VkFormat holds (float, signed or unsigned integers) and which uses Vulkan guarantees for it
// on every device ("Mandatory format support" in the Formats chapter of the Vulkan specification).
// The packager warns where a notation relies on support that some devices lack.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

namespace statepack::packager {

// How shaders see a format's values: UNORM, SNORM, SFLOAT, UFLOAT, SRGB and the SCALED formats read and
// write floats; SINT and UINT formats signed and unsigned integers.
enum class NumericClass { floating, signed_int, unsigned_int, none };

NumericClass numeric_class(uint32_t vk_format);
const char* numeric_class_name(NumericClass c);  // "float", "signed integer", "unsigned integer"

// The notation's name of a format (e.g. RGBA8_UNORM), else Vulkan's (VK_FORMAT_R8G8B8_SINT).
std::string format_name(uint32_t vk_format);
// Vulkan's name of a format: VK_FORMAT_R16G16B16A16_SFLOAT.
std::string vulkan_format_name(uint32_t vk_format);
// Vulkan's upper-case name from vulkan.hpp's CamelCase one (vk::to_string): ("VK_FORMAT_",
// "R16G16B16A16Sfloat") -> "VK_FORMAT_R16G16B16A16_SFLOAT".
std::string vulkan_upper_name(std::string_view prefix, std::string_view camel);

// Guaranteed by Vulkan 1.0 on every device.
bool guaranteed_color_attachment(uint32_t vk_format);
bool guaranteed_color_blend(uint32_t vk_format);
bool guaranteed_vertex_buffer(uint32_t vk_format);

}  // namespace statepack::packager
