#include "spellings.hpp"

#include <cctype>
#include <vulkan/vulkan.hpp>  // vk::to_string: Vulkan's own names, kept up to date by the SDK

namespace statepack::packager {

std::string vulkan_name(std::string_view prefix, std::string_view camel) {
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

std::string notation_name(EnumTable table, uint32_t value, const std::string& vulkan) {
  for (const auto& [name, v] : table)
    if (v == value && v != kUnsupportedValue) return std::string(name);
  return vulkan;
}

std::string vulkan_format_name(uint32_t format) {
  return vulkan_name("VK_FORMAT_", vk::to_string(vk::Format(format)));
}

}  // namespace statepack::packager
