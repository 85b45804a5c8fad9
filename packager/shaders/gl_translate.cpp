#include "gl_translate.hpp"

#include <spirv_cross_c.h>

#include <algorithm>
#include <array>
#include <set>
#include <string_view>
#include <tuple>

#include "format/archive_format.hpp"
#include "spirv_cross_context.hpp"

namespace statepack::packager {
namespace {

// Vulkan features OpenGL 4.5 (with GL_ARB_gl_spirv) has no form for, by the capability that declares
// them; said by name instead of a glslang error about generated text.
struct Refused {
  SpvCapability capability;
  const char* feature;
};
constexpr Refused kRefusedCapabilities[] = {
    {SpvCapabilityInputAttachment, "input attachments (subpassInput; OpenGL has no subpasses)"},
    {SpvCapabilityPhysicalStorageBufferAddresses, "buffer device addresses (buffer_reference)"},
    {SpvCapabilityRayQueryKHR, "ray queries (GL_EXT_ray_query)"},
    {SpvCapabilityMultiView, "multiview (gl_ViewIndex)"},
    {SpvCapabilityDrawParameters, "draw parameters (gl_BaseVertex, gl_BaseInstance, gl_DrawID)"},
    {SpvCapabilityRuntimeDescriptorArray, "runtime-sized descriptor arrays (descriptor indexing)"},
    {SpvCapabilityShaderNonUniform, "nonuniformEXT descriptor indexing"},
    {SpvCapabilityFragmentShadingRateKHR, "fragment shading rates"},
    {SpvCapabilityStorageBuffer8BitAccess, "8-bit storage buffer access"},
    {SpvCapabilityUniformAndStorageBuffer8BitAccess, "8-bit uniform buffer access"},
    {SpvCapabilityStoragePushConstant8, "8-bit push constants"},
    {SpvCapabilityStorageBuffer16BitAccess, "16-bit storage buffer access"},
    {SpvCapabilityUniformAndStorageBuffer16BitAccess, "16-bit uniform buffer access"},
    {SpvCapabilityStoragePushConstant16, "16-bit push constants"},
    {SpvCapabilityStorageInputOutput16, "16-bit stage inputs and outputs"},
    {SpvCapabilityDeviceGroup, "device groups (gl_DeviceIndex)"},
    {SpvCapabilityFragmentDensityEXT, "fragment density maps"},
    {SpvCapabilityVulkanMemoryModel, "the Vulkan memory model"},
    {SpvCapabilityFragmentShaderPixelInterlockEXT, "fragment shader interlock"},
    {SpvCapabilityFragmentBarycentricKHR, "fragment shader barycentrics (gl_BaryCoordEXT)"},
    {SpvCapabilitySparseResidency, "sparse residency (sparseTexture*ARB)"},
    {SpvCapabilityMinLod, "minimum-LOD clamps (texture*ClampARB)"},
    {SpvCapabilityInt64Atomics, "64-bit atomics"},
    {SpvCapabilityInt16, "16-bit integers"},
    {SpvCapabilityInt8, "8-bit integers"},
    {SpvCapabilityFloat16, "16-bit floats"},
};

// What stops the translation before it starts, by name; empty when nothing does.
std::string refused_features(spvc_compiler compiler, spvc_resources resources) {
  std::string out;
  auto add = [&](const std::string& what) { out += (out.empty() ? "" : ", ") + what; };
  const SpvCapability* capabilities = nullptr;
  size_t count = 0;
  spvc_compiler_get_declared_capabilities(compiler, &capabilities, &count);
  for (const Refused& r : kRefusedCapabilities)
    if (std::find(capabilities, capabilities + count, r.capability) != capabilities + count) add(r.feature);
  const spvc_reflected_resource* list = nullptr;
  spvc_resources_get_resource_list_for_type(resources, SPVC_RESOURCE_TYPE_ACCELERATION_STRUCTURE, &list,
                                            &count);
  if (count > 0) add("acceleration structures (ray tracing)");
  spvc_resources_get_resource_list_for_type(resources, SPVC_RESOURCE_TYPE_SUBPASS_INPUT, &list, &count);
  if (count > 0 && out.find("input attachments") == std::string::npos)
    add("input attachments (subpassInput; OpenGL has no subpasses)");
  return out;
}

// One resource the GLSL declares, in Vulkan's declaration order.
struct Declared {
  uint32_t set = 0, binding = 0;
  std::string name;
  spvc_variable_id id = 0;
  format::GlNamespace kind = format::GlNamespace::uniform_buffer;
  uint32_t elements = 1;        // an array's take one binding each
  bool separate_image = false;  // its combined samplers take its place
  bool push_constants = false;  // after every other resource
  auto key() const { return std::tie(push_constants, set, binding, name); }
};

// SPIRV-Cross writes a specialization constant, outside Vulkan semantics, as a macro the application
// would define when compiling GLSL at run time:
//   #ifndef SPIRV_CROSS_CONSTANT_ID_3
//   #define SPIRV_CROSS_CONSTANT_ID_3 64u
//   #endif
//   const uint kCount = SPIRV_CROSS_CONSTANT_ID_3;
// GL_ARB_gl_spirv has real specialization constants (glSpecializeShader), so the declaration gets its
// constant_id back. (Work-group sizes given by constants stay the macro: their default values.)
void restore_specialization_constants(std::string& glsl) {
  static constexpr std::string_view kMacro = " = SPIRV_CROSS_CONSTANT_ID_";
  std::string out;
  out.reserve(glsl.size() + 256);
  size_t start = 0;
  while (start < glsl.size()) {
    size_t end = glsl.find('\n', start);
    if (end == std::string::npos) end = glsl.size();
    std::string_view line(glsl.data() + start, end - start);
    const size_t at = line.find(kMacro);
    if (line.starts_with("const ") && at != std::string_view::npos && line.ends_with(";")) {
      std::string_view id = line.substr(at + kMacro.size());
      id.remove_suffix(1);
      if (!id.empty() && id.find_first_not_of("0123456789") == std::string_view::npos)
        out += "layout(constant_id = " + std::string(id) + ") ";
    }
    out += line;
    out += '\n';
    start = end + 1;
  }
  glsl = std::move(out);
}

}  // namespace

GlTranslation translate_for_opengl(std::span<const uint32_t> spirv, const std::string& sampler_suffix) {
  GlTranslation out;
  SpirvCrossContext ctx;
  spvc_parsed_ir ir = nullptr;
  spvc_compiler compiler = nullptr;
  spvc_resources resources = nullptr;
  spvc_compiler_options options = nullptr;
  auto failed = [&] {
    out.error =
        ctx.handle ? spvc_context_get_last_error_string(ctx.handle) : "cannot create a SPIRV-Cross context";
    while (!out.error.empty() && (out.error.back() == '\n' || out.error.back() == ' ')) out.error.pop_back();
    return out;
  };
  if (spvc_context_create(&ctx.handle) != SPVC_SUCCESS ||
      spvc_context_parse_spirv(ctx.handle, spirv.data(), spirv.size(), &ir) != SPVC_SUCCESS ||
      spvc_context_create_compiler(ctx.handle, SPVC_BACKEND_GLSL, ir, SPVC_CAPTURE_MODE_TAKE_OWNERSHIP,
                                   &compiler) != SPVC_SUCCESS ||
      spvc_compiler_create_shader_resources(compiler, &resources) != SPVC_SUCCESS)
    return failed();
  out.unsupported = refused_features(compiler, resources);
  if (!out.unsupported.empty()) return out;

  if (spvc_compiler_create_compiler_options(compiler, &options) != SPVC_SUCCESS) return failed();
  spvc_compiler_options_set_uint(options, SPVC_COMPILER_OPTION_GLSL_VERSION, 450);
  spvc_compiler_options_set_bool(options, SPVC_COMPILER_OPTION_GLSL_ES, SPVC_FALSE);
  spvc_compiler_options_set_bool(options, SPVC_COMPILER_OPTION_GLSL_VULKAN_SEMANTICS, SPVC_FALSE);
  spvc_compiler_options_set_bool(options, SPVC_COMPILER_OPTION_GLSL_EMIT_PUSH_CONSTANT_AS_UNIFORM_BUFFER,
                                 SPVC_TRUE);
  // gl_InstanceIndex becomes gl_InstanceID, not gl_InstanceID + a loose uniform SPIRV-Cross would add
  // for the base instance: the archive binds no loose uniforms (docs/cli.md says what that means).
  spvc_compiler_options_set_bool(options, SPVC_COMPILER_OPTION_GLSL_SUPPORT_NONZERO_BASE_INSTANCE,
                                 SPVC_FALSE);
  spvc_compiler_options_set_bool(options, SPVC_COMPILER_OPTION_GLSL_ENABLE_420PACK_EXTENSION, SPVC_TRUE);
  if (spvc_compiler_install_compiler_options(compiler, options) != SPVC_SUCCESS) return failed();

  // OpenGL samples through combined samplers only: every (image, sampler) pair the code uses becomes
  // one, and an image read without a sampler (texelFetch, HLSL's Load) is paired with a dummy one.
  spvc_variable_id dummy = 0;
  if (spvc_compiler_build_dummy_sampler_for_combined_images(compiler, &dummy) != SPVC_SUCCESS ||
      spvc_compiler_build_combined_image_samplers(compiler) != SPVC_SUCCESS)
    return failed();
  const spvc_combined_image_sampler* combined = nullptr;
  size_t combined_count = 0;
  if (spvc_compiler_get_combined_image_samplers(compiler, &combined, &combined_count) != SPVC_SUCCESS)
    return failed();

  std::vector<Declared> declared;
  using Kind = format::GlNamespace;
  auto collect = [&](spvc_resource_type type, Kind kind, bool separate_image, bool push_constants) {
    const spvc_reflected_resource* list = nullptr;
    size_t count = 0;
    spvc_resources_get_resource_list_for_type(resources, type, &list, &count);
    for (size_t i = 0; i < count; ++i) {
      spvc_type t = spvc_compiler_get_type_handle(compiler, list[i].type_id);
      uint32_t elements = 1;
      for (unsigned d = 0; d < spvc_type_get_num_array_dimensions(t); ++d)
        elements *= std::max<uint32_t>(1, spvc_type_get_array_dimension(t, d));
      declared.push_back({spvc_compiler_get_decoration(compiler, list[i].id, SpvDecorationDescriptorSet),
                          spvc_compiler_get_decoration(compiler, list[i].id, SpvDecorationBinding),
                          list[i].name, list[i].id, kind, elements, separate_image, push_constants});
    }
  };
  collect(SPVC_RESOURCE_TYPE_UNIFORM_BUFFER, Kind::uniform_buffer, false, false);
  collect(SPVC_RESOURCE_TYPE_STORAGE_BUFFER, Kind::storage_buffer, false, false);
  collect(SPVC_RESOURCE_TYPE_SAMPLED_IMAGE, Kind::texture, false, false);
  collect(SPVC_RESOURCE_TYPE_STORAGE_IMAGE, Kind::image, false, false);
  collect(SPVC_RESOURCE_TYPE_SEPARATE_IMAGE, Kind::texture, true, false);
  collect(SPVC_RESOURCE_TYPE_PUSH_CONSTANT, Kind::uniform_buffer, false, true);
  std::sort(declared.begin(), declared.end(),
            [](const Declared& a, const Declared& b) { return a.key() < b.key(); });

  auto name_of = [&](spvc_variable_id id) {
    const char* name = spvc_compiler_get_name(compiler, id);
    return std::string(name ? name : "");
  };
  std::set<std::string> taken;
  for (const Declared& d : declared) taken.insert(d.name);
  // Binding numbers per namespace, each element of an array taking one (glslang checks texture and
  // image bindings against OpenGL's units).
  std::array<uint32_t, format::kGlNamespaceCount> next_of{};
  for (const Declared& d : declared) {
    uint32_t& next = next_of[size_t(d.kind)];
    if (!d.separate_image) {
      spvc_compiler_set_decoration(compiler, d.id, SpvDecorationBinding, next);
      spvc_compiler_set_decoration(compiler, d.id, SpvDecorationDescriptorSet, 0);
      out.name_of_binding[{uint32_t(d.kind), next}] = d.push_constants ? kGlPushConstantsName : d.name;
      next += d.elements;
      continue;
    }
    std::vector<const spvc_combined_image_sampler*> pairs;
    for (size_t i = 0; i < combined_count; ++i)
      if (combined[i].image_id == d.id) pairs.push_back(&combined[i]);
    for (const spvc_combined_image_sampler* pair : pairs) {
      const std::string sampler = pair->sampler_id == dummy ? "" : name_of(pair->sampler_id);
      std::string name = d.name;
      if (pairs.size() > 1 && sampler != d.name + sampler_suffix) name += "_" + sampler;
      if (name != d.name && !taken.insert(name).second) name += "_" + std::to_string(next);  // still unique
      spvc_compiler_set_name(compiler, pair->combined_id, name.c_str());
      spvc_compiler_set_decoration(compiler, pair->combined_id, SpvDecorationBinding, next);
      spvc_compiler_set_decoration(compiler, pair->combined_id, SpvDecorationDescriptorSet, 0);
      out.name_of_binding[{uint32_t(d.kind), next}] = name;
      next += d.elements;
    }
  }

  const char* source = nullptr;
  if (spvc_compiler_compile(compiler, &source) != SPVC_SUCCESS) return failed();
  out.glsl = source;
  restore_specialization_constants(out.glsl);
  return out;
}

}  // namespace statepack::packager
