// A light SPIR-V reader: just enough of a module to check it against the archive's stored layouts
// before Vulkan sees it (entry points, descriptor bindings, push constants, vertex inputs). It is not
// a validator and links no SPIR-V library: the dearchiver stays free of shader compilers.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "statepack/result.hpp"

namespace statepack::spirv {

// What a descriptor binding must be to match a shader resource, as a set of VkDescriptorType bits
// (bit n: VkDescriptorType n, core types 0-10).
using DescriptorTypeMask = uint32_t;

struct Resource {
  uint32_t variable = 0;  // result id of the OpVariable
  uint32_t set = 0, binding = 0;
  DescriptorTypeMask compatible = 0;  // 0: a kind no core descriptor type holds
  uint32_t array_size = 1;            // elements the binding must hold at least (0: runtime array)
};

// The numeric type of a shader interface variable's components, to match attachment and vertex formats.
enum class Numeric : uint8_t { other, float_, sint, uint };

// The numeric type a VkFormat's components are read or written as (float for UNORM, SNORM, SCALED, SRGB
// and FLOAT formats; other for UNDEFINED). The packager's pack-time checks use it too, so pack and unpack
// classify formats alike.
Numeric numeric_of_format(uint32_t vk_format);

// A shader input or output with a location (built-ins have none).
struct Input {
  uint32_t variable = 0;
  uint32_t location = 0;
  uint32_t locations = 1;  // consecutive locations it occupies (matrices and arrays take several)
  Numeric numeric = Numeric::other;
};

struct PushConstantBlock {
  uint32_t variable = 0;
  uint32_t size = 0;  // bytes the block spans; 0 when its layout is not computed here
};

// One dimension of a compute shader's work-group size: a number, or a specialization constant's
// default that a pipeline may override.
struct WorkgroupDim {
  uint32_t value = 1;
  std::optional<uint32_t> spec_id;  // SpecId of the constant that sets it, when specializable
};

// `dims` with the values a pipeline gives its specializable dimensions (`specialized(spec_id)`; nullopt
// where it gives none, and the module's default stands). Pack and unpack size a work group alike.
using WorkgroupSize = std::array<uint64_t, 3>;
WorkgroupSize specialized_workgroup_size(const std::array<WorkgroupDim, 3>& dims,
                                         const std::function<std::optional<uint32_t>(uint32_t)>& specialized);
// "32 x 32 x 2", for messages.
[[gnu::cold]] std::string workgroup_size_text(const WorkgroupSize& size);

struct EntryPoint {
  uint32_t execution_model = 0;  // SpvExecutionModel
  uint32_t function = 0;         // id of its OpFunction
  std::string name;
  std::vector<uint32_t> interface;  // ids listed by OpEntryPoint, sorted
  // A GLCompute entry point's work-group size: the WorkgroupSize built-in when the module decorates one
  // (it overrides the execution modes), else LocalSizeId, else LocalSize; none when it is none of these
  // or names an id this walker cannot evaluate (a computed constant).
  std::optional<std::array<WorkgroupDim, 3>> workgroup_size;
};

// A specialization constant the module declares: its SpecId and the byte size Vulkan's map entry for it
// must have (4 for booleans, as VkBool32).
// What a specialization constant's value means (its OpType), for showing it as a value, not bits.
enum class SpecKind : uint8_t { other, boolean, sint, uint, float_ };
struct SpecConstant {
  uint32_t constant_id = 0;
  uint32_t size = 0;  // 0: a type this walker does not size (a map entry for it is refused)
  SpecKind kind = SpecKind::other;
};

struct Module {
  uint32_t version = 0;  // 0x00MMmm00
  uint32_t bound = 0;
  std::vector<EntryPoint> entry_points;
  std::vector<Resource> resources;  // every descriptor variable of the module
  std::vector<Input> inputs;        // every Input variable with a Location
  std::vector<Input> outputs;       // every Output variable with a Location
  std::optional<PushConstantBlock> push_constants;
  bool writes_point_size = false;            // point lists need it from the last pre-rasterization stage
  std::vector<SpecConstant> spec_constants;  // sorted by constant_id
  std::vector<uint32_t> capabilities;        // every OpCapability, in module order

  const SpecConstant* find_spec_constant(uint32_t constant_id) const;
  // Bit i set: an output occupies location i (0-31). For a fragment shader, the render targets it
  // writes, which a pipeline must give a target each (pack says so, unpack insists once patched).
  uint32_t output_location_mask() const;

  const EntryPoint* find(uint32_t execution_model, std::string_view name) const;
  // Whether the entry point may use the variable: from SPIR-V 1.4 on, its interface lists every global
  // it uses; before, only inputs and outputs, so any module-scope variable counts as used.
  bool uses(const EntryPoint& entry, uint32_t variable) const;
};

// Walks the module: header (magic, version, bound), every instruction's word count, then the
// declarations above. The error message says what is wrong and at which word.
Result<Module> walk(std::span<const uint32_t> words);

// The SpvExecutionModel of a VkShaderStageFlagBits stage (vertex to compute), or nullopt.
std::optional<uint32_t> execution_model_of_stage(uint32_t stage);

// "vertex", "fragment", ... for messages.
const char* stage_name(uint32_t stage);

}  // namespace statepack::spirv
