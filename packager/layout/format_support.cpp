#include "format_support.hpp"

#include <vulkan/vulkan.hpp>  // vk::to_string: Vulkan's names of every format

#include <algorithm>
#include <cctype>
#include <initializer_list>

#include "format/spirv_walk.hpp"
#include "notation/enum_tables.hpp"

namespace statepack::packager {
namespace {

bool listed(std::initializer_list<VkFormat> list, uint32_t format) {
  return std::find(list.begin(), list.end(), static_cast<VkFormat>(format)) != list.end();
}

}  // namespace

NumericClass numeric_class(uint32_t vk_format) {
  switch (spirv::numeric_of_format(vk_format)) {  // the dearchiver's classification, so both sides agree
    case spirv::Numeric::float_:
      return NumericClass::floating;
    case spirv::Numeric::sint:
      return NumericClass::signed_int;
    case spirv::Numeric::uint:
      return NumericClass::unsigned_int;
    case spirv::Numeric::other:
      break;
  }
  return NumericClass::none;
}

const char* numeric_class_name(NumericClass c) {
  switch (c) {
    case NumericClass::floating:
      return "float";
    case NumericClass::signed_int:
      return "signed integer";
    case NumericClass::unsigned_int:
      return "unsigned integer";
    case NumericClass::none:
      break;
  }
  return "unknown";
}

std::string vulkan_upper_name(std::string_view prefix, std::string_view camel) {
  std::string out(prefix);
  auto is = [&](size_t i, int (*test)(int)) {
    return i < camel.size() && test(static_cast<unsigned char>(camel[i]));
  };
  for (size_t i = 0; i < camel.size(); ++i) {
    // A word starts at a capital after a small letter (ColorAttachment), or after a digit when a small
    // letter follows (R8G8B8A8Unorm, Bc1RgbUnormBlock); runs of capitals stay together (PresentSrcKHR).
    if (is(i, std::isupper) && i > 0 &&
        (is(i - 1, std::islower) || (is(i - 1, std::isdigit) && is(i + 1, std::islower))))
      out += '_';
    out += static_cast<char>(std::toupper(static_cast<unsigned char>(camel[i])));
  }
  return out;
}

std::string vulkan_format_name(uint32_t vk_format) {
  return vulkan_upper_name("VK_FORMAT_", vk::to_string(vk::Format(vk_format)));
}

std::string format_name(uint32_t vk_format) {
  for (const auto& [name, value] : kTextureFormats)
    if (value == vk_format) return std::string(name);
  return vulkan_format_name(vk_format);
}

// The lists below are the specification's tables of mandatory format support (Vulkan 1.0 core).
bool guaranteed_color_attachment(uint32_t f) {
  return listed({VK_FORMAT_R5G6B5_UNORM_PACK16,
                 VK_FORMAT_A1R5G5B5_UNORM_PACK16,
                 VK_FORMAT_R8_UNORM,
                 VK_FORMAT_R8_UINT,
                 VK_FORMAT_R8_SINT,
                 VK_FORMAT_R8G8_UNORM,
                 VK_FORMAT_R8G8_UINT,
                 VK_FORMAT_R8G8_SINT,
                 VK_FORMAT_R8G8B8A8_UNORM,
                 VK_FORMAT_R8G8B8A8_SRGB,
                 VK_FORMAT_R8G8B8A8_UINT,
                 VK_FORMAT_R8G8B8A8_SINT,
                 VK_FORMAT_B8G8R8A8_UNORM,
                 VK_FORMAT_B8G8R8A8_SRGB,
                 VK_FORMAT_A8B8G8R8_UNORM_PACK32,
                 VK_FORMAT_A8B8G8R8_SRGB_PACK32,
                 VK_FORMAT_A8B8G8R8_UINT_PACK32,
                 VK_FORMAT_A8B8G8R8_SINT_PACK32,
                 VK_FORMAT_A2B10G10R10_UNORM_PACK32,
                 VK_FORMAT_A2B10G10R10_UINT_PACK32,
                 VK_FORMAT_R16_UINT,
                 VK_FORMAT_R16_SINT,
                 VK_FORMAT_R16_SFLOAT,
                 VK_FORMAT_R16G16_UINT,
                 VK_FORMAT_R16G16_SINT,
                 VK_FORMAT_R16G16_SFLOAT,
                 VK_FORMAT_R16G16B16A16_UINT,
                 VK_FORMAT_R16G16B16A16_SINT,
                 VK_FORMAT_R16G16B16A16_SFLOAT,
                 VK_FORMAT_R32_UINT,
                 VK_FORMAT_R32_SINT,
                 VK_FORMAT_R32_SFLOAT,
                 VK_FORMAT_R32G32_UINT,
                 VK_FORMAT_R32G32_SINT,
                 VK_FORMAT_R32G32_SFLOAT,
                 VK_FORMAT_R32G32B32A32_UINT,
                 VK_FORMAT_R32G32B32A32_SINT,
                 VK_FORMAT_R32G32B32A32_SFLOAT},
                f);
}

bool guaranteed_color_blend(uint32_t f) {
  return listed({VK_FORMAT_R5G6B5_UNORM_PACK16, VK_FORMAT_A1R5G5B5_UNORM_PACK16, VK_FORMAT_R8_UNORM,
                 VK_FORMAT_R8G8_UNORM, VK_FORMAT_R8G8B8A8_UNORM, VK_FORMAT_R8G8B8A8_SRGB,
                 VK_FORMAT_B8G8R8A8_UNORM, VK_FORMAT_B8G8R8A8_SRGB, VK_FORMAT_A8B8G8R8_UNORM_PACK32,
                 VK_FORMAT_A8B8G8R8_SRGB_PACK32, VK_FORMAT_A2B10G10R10_UNORM_PACK32, VK_FORMAT_R16_SFLOAT,
                 VK_FORMAT_R16G16_SFLOAT, VK_FORMAT_R16G16B16A16_SFLOAT},
                f);
}

bool guaranteed_vertex_buffer(uint32_t f) {
  return listed({VK_FORMAT_R8_UNORM,
                 VK_FORMAT_R8_SNORM,
                 VK_FORMAT_R8_UINT,
                 VK_FORMAT_R8_SINT,
                 VK_FORMAT_R8G8_UNORM,
                 VK_FORMAT_R8G8_SNORM,
                 VK_FORMAT_R8G8_UINT,
                 VK_FORMAT_R8G8_SINT,
                 VK_FORMAT_R8G8B8A8_UNORM,
                 VK_FORMAT_R8G8B8A8_SNORM,
                 VK_FORMAT_R8G8B8A8_UINT,
                 VK_FORMAT_R8G8B8A8_SINT,
                 VK_FORMAT_B8G8R8A8_UNORM,
                 VK_FORMAT_A8B8G8R8_UNORM_PACK32,
                 VK_FORMAT_A8B8G8R8_SNORM_PACK32,
                 VK_FORMAT_A8B8G8R8_UINT_PACK32,
                 VK_FORMAT_A8B8G8R8_SINT_PACK32,
                 VK_FORMAT_A2B10G10R10_UNORM_PACK32,
                 VK_FORMAT_R16_UNORM,
                 VK_FORMAT_R16_SNORM,
                 VK_FORMAT_R16_UINT,
                 VK_FORMAT_R16_SINT,
                 VK_FORMAT_R16_SFLOAT,
                 VK_FORMAT_R16G16_UNORM,
                 VK_FORMAT_R16G16_SNORM,
                 VK_FORMAT_R16G16_UINT,
                 VK_FORMAT_R16G16_SINT,
                 VK_FORMAT_R16G16_SFLOAT,
                 VK_FORMAT_R16G16B16A16_UNORM,
                 VK_FORMAT_R16G16B16A16_SNORM,
                 VK_FORMAT_R16G16B16A16_UINT,
                 VK_FORMAT_R16G16B16A16_SINT,
                 VK_FORMAT_R16G16B16A16_SFLOAT,
                 VK_FORMAT_R32_UINT,
                 VK_FORMAT_R32_SINT,
                 VK_FORMAT_R32_SFLOAT,
                 VK_FORMAT_R32G32_UINT,
                 VK_FORMAT_R32G32_SINT,
                 VK_FORMAT_R32G32_SFLOAT,
                 VK_FORMAT_R32G32B32_UINT,
                 VK_FORMAT_R32G32B32_SINT,
                 VK_FORMAT_R32G32B32_SFLOAT,
                 VK_FORMAT_R32G32B32A32_UINT,
                 VK_FORMAT_R32G32B32A32_SINT,
                 VK_FORMAT_R32G32B32A32_SFLOAT},
                f);
}

}  // namespace statepack::packager
