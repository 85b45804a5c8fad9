// Descriptor bindings and push constants of a SPIR-V module (spirv-cross C API).
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace statepack::packager {

struct ReflectedBinding {
  std::string name;
  uint32_t variable = 0;    // result id of its OpVariable
  uint32_t block_size = 0;  // uniform and storage blocks: their declared size in bytes
  uint32_t set = 0;
  uint32_t binding = 0;
  uint32_t descriptor_type = 0;  // VkDescriptorType
  uint32_t count = 1;
  uint32_t stage = 0;  // VkShaderStageFlagBits of the module
  // Word offsets of the DescriptorSet and Binding literals, for patching (0 when absent).
  uint32_t set_word = 0, binding_word = 0;
  // Uniform and storage blocks: their members (names, types, offsets, strides) as text, equal exactly
  // when two stages declare the same block; OpenGL links one definition per block (empty otherwise).
  std::string block_layout;
  // A texture or sampler declared [[vk::combinedImageSampler]] (HLSL): paired with the sampler or
  // texture at the same set and binding into one combined image sampler descriptor.
  bool combined_attribute = false;
};

// A specialization constant the module declares (SpecId), by the name the source gave it.
struct ReflectedConstant {
  enum class Kind { boolean, int32, uint32, float32, int64, uint64, float64, other } kind = Kind::other;
  std::string name;
  uint32_t constant_id = 0;
  uint32_t size = 4;  // bytes in a VkSpecializationMapEntry (booleans: 4, a VkBool32)
};

// A user-defined stage input or output (built-ins are left out), one per location-occupying value:
// block members are listed one by one. Per-vertex arrays of tessellation and geometry stages are
// listed per vertex (their outer array removed), as they match the neighbouring stage's plain values.
struct InterfaceVariable {
  enum class Base { floating, signed_int, unsigned_int, other } base = Base::other;  // other: structs, bools
  std::string name;
  uint32_t variable = 0;  // result id of its OpVariable (block members share their block's)
  uint32_t location = 0, component = 0;
  uint32_t bit_width = 32, vector_size = 1, columns = 1;
  uint32_t array_size = 1;  // elements, each taking `locations_per_element()` locations
  bool flat = false, patch = false;
  // A column (a vector) takes a second location when its 32-bit words run past component 3.
  uint32_t locations_per_column() const {
    return vector_size * (bit_width == 64 ? 2 : 1) + component > 4 ? 2 : 1;
  }
  uint32_t locations_per_element() const { return columns * locations_per_column(); }
};

struct Reflection {
  std::vector<ReflectedBinding> bindings;
  std::vector<InterfaceVariable> inputs, outputs;
  std::vector<ReflectedConstant> constants;
  uint32_t push_constant_size = 0;
  std::string push_constant_name;  // the push-constant block's name, when it has one
  std::string error;               // non-empty when reflection failed
  // Non-empty when the module declares a resource of a kind statepack does not pack (an acceleration
  // structure): what it is, by name, set and binding.
  std::string unsupported;
};

Reflection reflect_spirv(std::span<const uint32_t> spirv, uint32_t stage);

}  // namespace statepack::packager
