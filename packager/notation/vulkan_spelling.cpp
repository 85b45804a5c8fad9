#include "vulkan_spelling.hpp"

#include <vulkan/vulkan.hpp>  // vk::to_string: Vulkan's names of every enum value

#include <cctype>
#include <string>

namespace statepack::packager {
namespace {

// Letters and digits only, lower case: "VK_FORMAT_R8G8B8A8_UNORM" and "R8G8B8A8Unorm" meet.
std::string normalized(std::string_view text) {
  std::string out;
  for (char c : text)
    if (std::isalnum(static_cast<unsigned char>(c))) out += char(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

// Vulkan's name of a value of `table`, or empty for tables that are not a Vulkan enum.
std::string vulkan_name(EnumTable table, uint32_t value) {
  auto is = [&](EnumTable t) { return table.data() == t.data(); };
  if (is(kTextureFormats)) return vk::to_string(vk::Format(value));
  if (is(kShaderTypes) || is(kShaderStageFlags)) return vk::to_string(vk::ShaderStageFlagBits(value));
  if (is(kTopologies)) return vk::to_string(vk::PrimitiveTopology(value));
  if (is(kFillModes)) return vk::to_string(vk::PolygonMode(value));
  if (is(kCullModes)) return vk::to_string(vk::CullModeFlagBits(value));
  if (is(kComparisonFuncs)) return vk::to_string(vk::CompareOp(value));
  if (is(kStencilOps)) return vk::to_string(vk::StencilOp(value));
  if (is(kBlendFactors)) return vk::to_string(vk::BlendFactor(value));
  if (is(kBlendOps)) return vk::to_string(vk::BlendOp(value));
  if (is(kLoadOps)) return vk::to_string(vk::AttachmentLoadOp(value));
  if (is(kStoreOps)) return vk::to_string(vk::AttachmentStoreOp(value));
  if (is(kAddressModes)) return vk::to_string(vk::SamplerAddressMode(value));
  // FILTER_TYPE: POINT and LINEAR are VkFilter values; the comparison, anisotropic and minimum
  // variants have no single Vulkan spelling.
  if (is(kFilterTypes)) return value <= VK_FILTER_LINEAR ? vk::to_string(vk::Filter(value)) : std::string();
  // Dynamic states are stored as statepack's bits, but named as Vulkan names them (VIEWPORT is
  // VK_DYNAMIC_STATE_VIEWPORT).
  if (is(kDynamicStates))
    for (const auto& [name, bit] : table)
      if (bit == value) return std::string(name);
  return {};
}

}  // namespace

std::optional<std::string_view> notation_name_for_vulkan_spelling(EnumTable table, std::string_view text) {
  std::string wanted = normalized(text);
  if (wanted.size() > 3 && wanted.ends_with("bit")) wanted.resize(wanted.size() - 3);  // flag bits' _BIT
  if (wanted.size() > 2 && wanted.starts_with("vk")) {
    // "vk" + the type's name ("format", "compareop", ...) + the value's: the value whose name is the
    // longest suffix (so VK_COMPARE_OP_LESS_OR_EQUAL is LESS_OR_EQUAL, not EQUAL).
    std::optional<std::string_view> best;
    size_t best_length = 0;
    for (const auto& [name, value] : table) {
      if (value == kUnsupportedValue) continue;
      std::string vulkan = normalized(vulkan_name(table, value));
      if (vulkan.empty()) continue;  // a table, or a value, with no Vulkan name
      if (wanted.size() > vulkan.size() + 2 && wanted.ends_with(vulkan) && vulkan.size() > best_length)
        best = name, best_length = vulkan.size();
    }
    return best;
  }
  for (const auto& [name, value] : table) {
    if (value == kUnsupportedValue) continue;
    std::string vulkan = normalized(vulkan_name(table, value));
    if (vulkan.empty()) continue;
    if (vulkan == wanted) return name;
  }
  return std::nullopt;
}

}  // namespace statepack::packager
