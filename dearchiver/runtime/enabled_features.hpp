// The features the application created its device with, and what each SPIR-V capability needs of
// them: Vulkan's table of SPIR-V capabilities (vk.xml's <spirvcapabilities>, generated into
// spirv_capability_table.inc at build time by spirv_capability_gen.py). A shader module declaring a
// capability nothing enabled is refused before vkCreateShaderModule, naming what would allow it.
#pragma once

#include <vulkan/vulkan_core.h>

#include <map>
#include <set>
#include <string>
#include <vector>

#include "device_limits.hpp"
#include "statepack/dearchiver.hpp"

namespace statepack::detail {

class EnabledFeatures {
 public:
  // From DeviceContext: the feature chain (and 1.0 features, and extensions) the application gave;
  // what it left out (null) is off, as DeviceContext documents.
  static EnabledFeatures gather(const DeviceContext& context, const DeviceCaps& caps);

  const VkPhysicalDeviceFeatures& core() const { return core_; }
  // "" when every capability is allowed; else the first one that is not, and what would allow it.
  std::string check_capabilities(const std::vector<uint32_t>& capabilities) const;
  bool has_extension(std::string_view name) const { return extensions_.count(name) != 0; }

 private:
  // A feature or property structure's bytes by sType: a feature structure missing from the map is off;
  // `properties_known_`: the properties were queried (Vulkan 1.2), else a property row allows.
  std::map<uint32_t, std::vector<unsigned char>> features_, properties_;
  bool properties_known_ = false;
  std::set<std::string, std::less<>> extensions_;
  VkPhysicalDeviceFeatures core_{};
  uint32_t api_version_ = 0;
};

}  // namespace statepack::detail
