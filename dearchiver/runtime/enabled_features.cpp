#include "enabled_features.hpp"

#include <cstddef>
#include <cstring>

#include "spirv_capability_table.hpp"

namespace statepack::detail {
namespace {

using namespace capability_table;

size_t struct_size(uint32_t s_type) {
  for (const StructSize& s : kCapabilityStructs)
    if (uint32_t(s.s_type) == s_type) return s.size;
  return 0;
}

uint32_t word_at(const std::vector<unsigned char>& bytes, uint32_t offset) {
  uint32_t word = 0;
  if (offset + sizeof word <= bytes.size()) std::memcpy(&word, bytes.data() + offset, sizeof word);
  return word;
}

// Copies every structure of a pNext chain this table reads (the others are not ours to size).
void copy_chain(const void* chain, std::map<uint32_t, std::vector<unsigned char>>& into) {
  size_t guard = 0;  // a chain that loops back on itself ends here
  for (auto* s = static_cast<const VkBaseInStructure*>(chain); s && guard < 256; s = s->pNext, ++guard)
    if (size_t size = struct_size(uint32_t(s->sType))) {
      const auto* bytes = reinterpret_cast<const unsigned char*>(s);
      into[uint32_t(s->sType)].assign(bytes, bytes + size);
    }
}

// The Vulkan 1.1-1.2 properties of this device (subgroup operations, float controls, ...).
void query_properties(const DeviceCaps& caps, std::map<uint32_t, std::vector<unsigned char>>& into) {
  VkPhysicalDeviceVulkan12Properties p12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_PROPERTIES};
  VkPhysicalDeviceVulkan11Properties p11{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_1_PROPERTIES, &p12};
  VkPhysicalDeviceProperties2 p{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2, &p11};
  caps.vk.vkGetPhysicalDeviceProperties2(caps.physical_device, &p);
  copy_chain(&p11, into);
}

}  // namespace

EnabledFeatures EnabledFeatures::gather(const DeviceContext& context, const DeviceCaps& caps) {
  EnabledFeatures out;
  out.api_version_ = caps.properties.apiVersion;
  const bool queryable = out.api_version_ >= VK_API_VERSION_1_2;  // the Vulkan11/12 structures exist
  // What the application did not pass it did not enable, as for vkCreateDevice: a structure missing
  // from the chain (or no chain) is all off, no enabled_features is no core feature, no extension list
  // is no extension. Guessing "what the device supports" instead would let through what the validation
  // layer then reports.
  if (context.enabled_feature_chain) copy_chain(context.enabled_feature_chain, out.features_);
  // VkPhysicalDeviceFeatures: the chain's VkPhysicalDeviceFeatures2, else enabled_features.
  if (auto it = out.features_.find(VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2); it != out.features_.end())
    std::memcpy(&out.core_, it->second.data() + offsetof(VkPhysicalDeviceFeatures2, features),
                sizeof out.core_);
  else if (context.enabled_features)
    out.core_ = *context.enabled_features;
  VkPhysicalDeviceFeatures2 core2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2, nullptr, out.core_};
  copy_chain(&core2, out.features_);  // the 1.0 rows read it there, whichever way it came
  if (queryable && caps.vk.vkGetPhysicalDeviceProperties2) {
    query_properties(caps, out.properties_);
    out.properties_known_ = true;
  }
  if (context.enabled_extensions) {
    for (uint32_t i = 0; i < context.enabled_extension_count; ++i)
      if (context.enabled_extensions[i]) out.extensions_.insert(context.enabled_extensions[i]);
  }
  return out;
}

std::string EnabledFeatures::check_capabilities(const std::vector<uint32_t>& capabilities) const {
  auto allows = [&](const CapabilityEnable& e) {
    switch (e.kind) {
      case EnableKind::version:
        return api_version_ >= e.version;
      case EnableKind::feature: {
        auto it = features_.find(uint32_t(e.s_type));  // a structure the chain lacks is off
        return it != features_.end() && word_at(it->second, e.offset) != 0;
      }
      case EnableKind::extension:
        return extensions_.count(text(e.extension)) != 0;
      case EnableKind::property: {
        auto it = properties_.find(uint32_t(e.s_type));
        return it == properties_.end() ? !properties_known_
                                       : (word_at(it->second, e.offset) & e.bits) == e.bits;
      }
    }
    return false;
  };
  // Every way to allow a capability, in words: made only for a capability refused.
  auto ways = [&](uint32_t capability) {
    std::string needs;
    for (const CapabilityEnable& e : kCapabilityEnables) {
      if (e.capability != capability) continue;
      if (!needs.empty()) needs += ", ";
      switch (e.kind) {
        case EnableKind::version:
          needs += "Vulkan " + std::to_string(VK_API_VERSION_MAJOR(e.version)) + "." +
                   std::to_string(VK_API_VERSION_MINOR(e.version));
          break;
        case EnableKind::extension:
          needs += std::string("the extension ") + text(e.extension);
          break;
        case EnableKind::feature:
        case EnableKind::property:
          needs += std::string(text(e.what)) + "::" + text(e.member);
          break;
      }
    }
    return needs;
  };
  for (uint32_t capability : capabilities) {
    const char* name = nullptr;
    bool allowed = false;
    for (const CapabilityEnable& e : kCapabilityEnables) {
      if (e.capability != capability) continue;
      name = text(e.name);
      if ((allowed = allows(e))) break;
    }
    if (!name)
      return "declares the SPIR-V capability " + std::to_string(capability) +
             ", which Vulkan does not allow in shaders (it is not in Vulkan's table of SPIR-V capabilities)";
    if (!allowed)
      return "declares the SPIR-V capability " + std::string(name) +
             ", which needs one of: " + ways(capability) +
             "; none is enabled on this device (DeviceContext::enabled_feature_chain and enabled_extensions "
             "say what the device was created with)";
  }
  return "";
}

}  // namespace statepack::detail
