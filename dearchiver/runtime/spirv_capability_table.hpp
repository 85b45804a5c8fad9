// Vulkan's table of SPIR-V capabilities, generated at build time from vk.xml by
// spirv_capability_gen.py into spirv_capability_table.inc: how each capability may be allowed
// (enabled_features.cpp checks shaders against it), and the device extensions that allow capabilities
// (the bootstrap enables those a device has when it should run any archive, as statepack verify does).
#pragma once

#include <vulkan/vulkan_core.h>

#include <cstddef>
#include <cstdint>

namespace statepack::detail::capability_table {

enum class EnableKind : unsigned char { version, feature, extension, property };
struct StructSize {
  VkStructureType s_type;
  size_t size;
};
// One way to allow a capability (vk.xml's <enable>): any one of a capability's rows allows it.
// Its words are offsets into kCapabilityText (text() reads them): a table without pointers, so without
// a relocation per word in a position-independent program.
struct CapabilityEnable {
  uint32_t capability;
  uint16_t name;  // "Int8"
  EnableKind kind;
  uint32_t version;        // version: the core version that allows it
  VkStructureType s_type;  // feature, property: the structure
  uint32_t offset;         // ... and the VkBool32 / flags member's offset in it
  uint16_t what;           // the structure, "VkPhysicalDeviceVulkan12Features"
  uint16_t member;         // ... and its member, "shaderInt8" (a property's: "... with VK_TRUE")
  uint16_t extension;      // extension: the device extension that allows it
  uint32_t bits;           // property: the bits the member must have (1: VK_TRUE)
};
// A device extension that allows capabilities, and one of its feature structures (none: 0, 0).
struct ExtensionStruct {
  const char* extension;
  VkStructureType s_type;
  size_t size;
};
struct ExtensionDependency {
  const char* extension;
  const char* needs;  // a device extension it requires
};

#include "spirv_capability_table.inc"

inline const char* text(uint16_t offset) {
  return kCapabilityText + offset;
}

}  // namespace statepack::detail::capability_table
