#include "spirv_reflect.hpp"

#include <spirv_cross_c.h>
#include <vulkan/vulkan_core.h>

#include <algorithm>
#include <map>

#include "spirv_cross_context.hpp"

namespace statepack::packager {
namespace {

InterfaceVariable::Base base_of(spvc_type type) {
  switch (spvc_type_get_basetype(type)) {
    case SPVC_BASETYPE_FP16:
    case SPVC_BASETYPE_FP32:
    case SPVC_BASETYPE_FP64:
      return InterfaceVariable::Base::floating;
    case SPVC_BASETYPE_INT8:
    case SPVC_BASETYPE_INT16:
    case SPVC_BASETYPE_INT32:
    case SPVC_BASETYPE_INT64:
      return InterfaceVariable::Base::signed_int;
    case SPVC_BASETYPE_UINT8:
    case SPVC_BASETYPE_UINT16:
    case SPVC_BASETYPE_UINT32:
    case SPVC_BASETYPE_UINT64:
      return InterfaceVariable::Base::unsigned_int;
    default:
      return InterfaceVariable::Base::other;
  }
}

// Fills the scalar/vector/matrix shape of `v` from `type`; `skip_outer` drops the outermost array
// dimension (the per-vertex one; spirv-cross lists dimensions innermost first).
void fill_shape(spvc_type type, bool skip_outer, InterfaceVariable& v) {
  v.base = base_of(type);
  v.bit_width = spvc_type_get_bit_width(type);
  v.vector_size = spvc_type_get_vector_size(type);
  v.columns = spvc_type_get_columns(type);
  unsigned dims = spvc_type_get_num_array_dimensions(type);
  if (skip_outer && dims > 0) --dims;
  v.array_size = 1;
  for (unsigned d = 0; d < dims; ++d)
    v.array_size *= std::max<SpvId>(1, spvc_type_get_array_dimension(type, d));
}

void add_interface(spvc_compiler compiler, const spvc_reflected_resource* list, size_t count,
                   bool per_vertex_arrays, std::vector<InterfaceVariable>& out) {
  for (size_t i = 0; i < count; ++i) {
    const SpvId id = list[i].id;
    if (spvc_compiler_has_decoration(compiler, id, SpvDecorationBuiltIn)) continue;
    InterfaceVariable v;
    v.name = list[i].name;
    v.variable = id;
    v.patch = spvc_compiler_has_decoration(compiler, id, SpvDecorationPatch);
    v.flat = spvc_compiler_has_decoration(compiler, id, SpvDecorationFlat);
    const bool has_location = spvc_compiler_has_decoration(compiler, id, SpvDecorationLocation);
    v.location = spvc_compiler_get_decoration(compiler, id, SpvDecorationLocation);
    v.component = spvc_compiler_get_decoration(compiler, id, SpvDecorationComponent);
    // A fragment input declared pervertexEXT (PerVertexKHR, barycentric interpolation) is an array over
    // the triangle's vertices, like a geometry shader's inputs: it takes the locations of one element.
    const bool skip_outer = (per_vertex_arrays && !v.patch) ||
                            spvc_compiler_has_decoration(compiler, id, SpvDecorationPerVertexKHR);
    spvc_type type = spvc_compiler_get_type_handle(compiler, list[i].type_id);
    spvc_type base = spvc_compiler_get_type_handle(compiler, list[i].base_type_id);
    if (spvc_type_get_basetype(base) != SPVC_BASETYPE_STRUCT) {
      if (!has_location) continue;  // Vulkan requires one; nothing to match without it
      fill_shape(type, skip_outer, v);
      out.push_back(std::move(v));
      continue;
    }
    // A block: each member takes the next locations unless it names its own. An array of blocks
    // (other than the per-vertex one) is left out: rare, and its layout is not worth modelling.
    unsigned dims = spvc_type_get_num_array_dimensions(type);
    if (dims > (skip_outer ? 1u : 0u)) continue;
    uint32_t next = v.location;
    for (unsigned m = 0; m < spvc_type_get_num_member_types(base); ++m) {
      InterfaceVariable member = v;
      const char* member_name = spvc_compiler_get_member_name(compiler, list[i].base_type_id, m);
      member.name = v.name + "." + (member_name ? member_name : std::to_string(m));
      if (spvc_compiler_has_member_decoration(compiler, list[i].base_type_id, m, SpvDecorationLocation))
        next = spvc_compiler_get_member_decoration(compiler, list[i].base_type_id, m, SpvDecorationLocation);
      else if (!has_location)
        break;  // no location anywhere: nothing to match
      member.location = next;
      member.component =
          spvc_compiler_get_member_decoration(compiler, list[i].base_type_id, m, SpvDecorationComponent);
      member.flat =
          v.flat || spvc_compiler_has_member_decoration(compiler, list[i].base_type_id, m, SpvDecorationFlat);
      fill_shape(spvc_compiler_get_type_handle(compiler, spvc_type_get_member_type(base, m)), false, member);
      next += member.array_size * member.locations_per_element();
      out.push_back(std::move(member));
    }
  }
}

// A block type's members as text (see ReflectedBinding::block_layout). Each distinct struct type is
// written once, in first-use order, and a member of struct type names it by that number, so the text
// grows with the module's types, never with how often they nest (a struct of ten structs of ten
// structs ... would otherwise be written out 10^depth times), and no recursion follows the input.
std::string describe_block(spvc_compiler compiler, spvc_type_id block) {
  std::vector<spvc_type_id> structs{block};
  std::map<spvc_type_id, size_t> number{{block, 0}};
  std::string out;
  for (size_t k = 0; k < structs.size(); ++k) {
    const spvc_type_id id = structs[k];
    spvc_type type = spvc_compiler_get_type_handle(compiler, id);
    out += "#" + std::to_string(k) + "{";
    for (unsigned m = 0; m < spvc_type_get_num_member_types(type); ++m) {
      const spvc_type_id member_id = spvc_type_get_member_type(type, m);
      spvc_type member = spvc_compiler_get_type_handle(compiler, member_id);
      const char* name = spvc_compiler_get_member_name(compiler, id, m);
      unsigned offset = 0, array_stride = 0, matrix_stride = 0;
      spvc_compiler_type_struct_member_offset(compiler, type, m, &offset);
      spvc_compiler_type_struct_member_array_stride(compiler, type, m, &array_stride);
      spvc_compiler_type_struct_member_matrix_stride(compiler, type, m, &matrix_stride);
      out += std::string(name ? name : "") + "@" + std::to_string(offset) + "/" +
             std::to_string(array_stride) + "/" + std::to_string(matrix_stride) + ":" +
             std::to_string(int(spvc_type_get_basetype(member))) + "x" +
             std::to_string(spvc_type_get_vector_size(member)) + "x" +
             std::to_string(spvc_type_get_columns(member));
      for (unsigned d = 0; d < spvc_type_get_num_array_dimensions(member); ++d)
        out += "[" + std::to_string(spvc_type_get_array_dimension(member, d)) + "]";
      if (spvc_type_get_num_member_types(member) > 0) {
        auto [it, added] = number.try_emplace(member_id, structs.size());
        if (added) structs.push_back(member_id);
        out += "#" + std::to_string(it->second);
      }
      out += ";";
    }
    out += "}";
  }
  return out;
}

// The descriptor type of each spirv-cross resource list.
struct DescriptorKind {
  spvc_resource_type type;
  VkDescriptorType descriptor, buffer_descriptor;  // the second for images of dimension Buffer
};
constexpr DescriptorKind kDescriptorKinds[] = {
    {SPVC_RESOURCE_TYPE_UNIFORM_BUFFER, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER},
    {SPVC_RESOURCE_TYPE_STORAGE_BUFFER, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
    {SPVC_RESOURCE_TYPE_SAMPLED_IMAGE, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER,
     VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER},
    {SPVC_RESOURCE_TYPE_SEPARATE_IMAGE, VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE,
     VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER},
    {SPVC_RESOURCE_TYPE_STORAGE_IMAGE, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE,
     VK_DESCRIPTOR_TYPE_STORAGE_TEXEL_BUFFER},
    {SPVC_RESOURCE_TYPE_SEPARATE_SAMPLERS, VK_DESCRIPTOR_TYPE_SAMPLER, VK_DESCRIPTOR_TYPE_SAMPLER},
    {SPVC_RESOURCE_TYPE_SUBPASS_INPUT, VK_DESCRIPTOR_TYPE_INPUT_ATTACHMENT,
     VK_DESCRIPTOR_TYPE_INPUT_ATTACHMENT},
};

ReflectedBinding reflect_binding(spvc_compiler compiler, const spvc_reflected_resource& resource,
                                 const DescriptorKind& kind, uint32_t stage) {
  ReflectedBinding b;
  b.name = resource.name;
  b.variable = resource.id;
  b.set = spvc_compiler_get_decoration(compiler, resource.id, SpvDecorationDescriptorSet);
  b.binding = spvc_compiler_get_decoration(compiler, resource.id, SpvDecorationBinding);
  b.stage = stage;
  unsigned word = 0;
  if (spvc_compiler_get_binary_offset_for_decoration(compiler, resource.id, SpvDecorationDescriptorSet,
                                                     &word))
    b.set_word = word;
  if (spvc_compiler_get_binary_offset_for_decoration(compiler, resource.id, SpvDecorationBinding, &word))
    b.binding_word = word;
  spvc_type type = spvc_compiler_get_type_handle(compiler, resource.type_id);
  bool is_image = kind.type == SPVC_RESOURCE_TYPE_SAMPLED_IMAGE ||
                  kind.type == SPVC_RESOURCE_TYPE_SEPARATE_IMAGE ||
                  kind.type == SPVC_RESOURCE_TYPE_STORAGE_IMAGE;
  b.descriptor_type = (is_image && spvc_type_get_image_dimension(type) == SpvDimBuffer)
                          ? kind.buffer_descriptor
                          : kind.descriptor;
  if (kind.type == SPVC_RESOURCE_TYPE_UNIFORM_BUFFER || kind.type == SPVC_RESOURCE_TYPE_STORAGE_BUFFER) {
    b.block_layout = describe_block(compiler, resource.base_type_id);
    size_t size = 0;
    spvc_compiler_get_declared_struct_size(
        compiler, spvc_compiler_get_type_handle(compiler, resource.base_type_id), &size);
    b.block_size = static_cast<uint32_t>(size);
  }
  b.count = 1;
  for (unsigned d = 0; d < spvc_type_get_num_array_dimensions(type); ++d)
    b.count *= spvc_type_get_array_dimension(type, d);  // 0 for runtime arrays: caught by the packer
  return b;
}

void add_bindings(spvc_compiler compiler, spvc_resources resources, uint32_t stage,
                  std::vector<ReflectedBinding>& out) {
  for (const DescriptorKind& kind : kDescriptorKinds) {
    const spvc_reflected_resource* list = nullptr;
    size_t count = 0;
    spvc_resources_get_resource_list_for_type(resources, kind.type, &list, &count);
    for (size_t i = 0; i < count; ++i) out.push_back(reflect_binding(compiler, list[i], kind, stage));
  }
}

void add_stage_interfaces(spvc_compiler compiler, spvc_resources resources, uint32_t stage, Reflection& out) {
  // Tessellation and geometry stages read (and the control stage writes) one value per vertex.
  const bool arrayed_inputs = stage == VK_SHADER_STAGE_TESSELLATION_CONTROL_BIT ||
                              stage == VK_SHADER_STAGE_TESSELLATION_EVALUATION_BIT ||
                              stage == VK_SHADER_STAGE_GEOMETRY_BIT;
  const spvc_reflected_resource* list = nullptr;
  size_t count = 0;
  spvc_resources_get_resource_list_for_type(resources, SPVC_RESOURCE_TYPE_STAGE_INPUT, &list, &count);
  add_interface(compiler, list, count, arrayed_inputs, out.inputs);
  spvc_resources_get_resource_list_for_type(resources, SPVC_RESOURCE_TYPE_STAGE_OUTPUT, &list, &count);
  add_interface(compiler, list, count, stage == VK_SHADER_STAGE_TESSELLATION_CONTROL_BIT, out.outputs);
}

ReflectedConstant reflect_constant(spvc_compiler compiler, const spvc_specialization_constant& constant) {
  ReflectedConstant k;
  k.constant_id = constant.constant_id;
  const char* name = spvc_compiler_get_name(compiler, constant.id);
  k.name = name ? name : "";
  spvc_constant handle = spvc_compiler_get_constant_handle(compiler, constant.id);
  spvc_type type = spvc_compiler_get_type_handle(compiler, spvc_constant_get_type(handle));
  using ConstantKind = ReflectedConstant::Kind;
  switch (spvc_type_get_basetype(type)) {
    case SPVC_BASETYPE_BOOLEAN:
      k.kind = ConstantKind::boolean;
      break;
    case SPVC_BASETYPE_INT32:
      k.kind = ConstantKind::int32;
      break;
    case SPVC_BASETYPE_UINT32:
      k.kind = ConstantKind::uint32;
      break;
    case SPVC_BASETYPE_FP32:
      k.kind = ConstantKind::float32;
      break;
    case SPVC_BASETYPE_INT64:
      k.kind = ConstantKind::int64, k.size = 8;
      break;
    case SPVC_BASETYPE_UINT64:
      k.kind = ConstantKind::uint64, k.size = 8;
      break;
    case SPVC_BASETYPE_FP64:
      k.kind = ConstantKind::float64, k.size = 8;
      break;
    default:
      k.kind = ConstantKind::other;
      break;
  }
  return k;
}

uint32_t push_constant_size(spvc_compiler compiler, spvc_resources resources, std::string& name) {
  const spvc_reflected_resource* push = nullptr;
  size_t push_count = 0;
  spvc_resources_get_resource_list_for_type(resources, SPVC_RESOURCE_TYPE_PUSH_CONSTANT, &push, &push_count);
  if (push_count == 0) return 0;
  name = push[0].name ? push[0].name : "";
  size_t size = 0;
  spvc_compiler_get_declared_struct_size(
      compiler, spvc_compiler_get_type_handle(compiler, push[0].base_type_id), &size);
  return static_cast<uint32_t>(size);
}

}  // namespace

Reflection reflect_spirv(std::span<const uint32_t> spirv, uint32_t stage) {
  Reflection out;
  SpirvCrossContext ctx;
  spvc_parsed_ir ir = nullptr;
  spvc_compiler compiler = nullptr;
  spvc_resources resources = nullptr;
  if (spvc_context_create(&ctx.handle) != SPVC_SUCCESS ||
      spvc_context_parse_spirv(ctx.handle, spirv.data(), spirv.size(), &ir) != SPVC_SUCCESS ||
      spvc_context_create_compiler(ctx.handle, SPVC_BACKEND_NONE, ir, SPVC_CAPTURE_MODE_TAKE_OWNERSHIP,
                                   &compiler) != SPVC_SUCCESS ||
      spvc_compiler_create_shader_resources(compiler, &resources) != SPVC_SUCCESS) {
    out.error =
        ctx.handle ? spvc_context_get_last_error_string(ctx.handle) : "cannot create a spirv-cross context";
    return out;
  }
  add_bindings(compiler, resources, stage, out.bindings);
  // Ray queries' and ray tracing's acceleration structures are a descriptor type (and device features)
  // the archive does not hold: said at the shader, not found missing from the layout later.
  const spvc_reflected_resource* structures = nullptr;
  size_t structure_count = 0;
  spvc_resources_get_resource_list_for_type(resources, SPVC_RESOURCE_TYPE_ACCELERATION_STRUCTURE, &structures,
                                            &structure_count);
  if (structure_count > 0)
    out.unsupported =
        "declares acceleration structure '" + std::string(structures[0].name) + "' (set " +
        std::to_string(spvc_compiler_get_decoration(compiler, structures[0].id, SpvDecorationDescriptorSet)) +
        ", binding " +
        std::to_string(spvc_compiler_get_decoration(compiler, structures[0].id, SpvDecorationBinding)) +
        "): statepack does not pack ray-query or ray-tracing resources (VK_KHR_acceleration_structure)";
  add_stage_interfaces(compiler, resources, stage, out);
  const spvc_specialization_constant* constants = nullptr;
  size_t constant_count = 0;
  spvc_compiler_get_specialization_constants(compiler, &constants, &constant_count);
  for (size_t i = 0; i < constant_count; ++i)
    out.constants.push_back(reflect_constant(compiler, constants[i]));
  out.push_constant_size = push_constant_size(compiler, resources, out.push_constant_name);
  return out;
}

}  // namespace statepack::packager
