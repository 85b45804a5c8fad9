#include "semantic_check.hpp"

#include <algorithm>
#include <iterator>
#include <optional>

#include "spirv_walk.hpp"

namespace statepack::format {
namespace {

std::string type_names(spirv::DescriptorTypeMask mask) {
  std::string out;
  for (uint32_t t = 0; t < 11; ++t)
    if (mask & (1u << t)) out += std::string(out.empty() ? "" : " or ") + descriptor_type_name(t);
  return out;
}

// No device has more vertex attributes than this; an input claiming more is hostile.
constexpr uint32_t kMaxVertexLocations = 64;

Error corrupt(std::string message) {
  return Error{ErrorCode::corrupt, "corrupt archive: " + std::move(message)};
}

// The constants of one stage against its module: each declared, with the same size. A Vulkan map entry
// must match the size of the constant the shader declares (VUID-VkSpecializationMapEntry-constantID-00776);
// one the shader does not declare is harmless to Vulkan but a mistake of the archive, and an error for
// glSpecializeShader. `pipeline` and `who` name the pipeline and the shader in messages.
Result<void> check_constants(const spirv::Module& module, const std::vector<SpecConstant>& constants,
                             uint32_t stage, const std::string& pipeline, const std::string& who) {
  for (const SpecConstant& s : constants) {
    if (s.stage != stage) continue;
    const spirv::SpecConstant* declared = module.find_spec_constant(s.constant_id);
    const std::string what =
        pipeline + ": specialization constant '" + s.name + "' (id " + std::to_string(s.constant_id) + ")";
    if (!declared) return corrupt(what + " is not declared by " + who);
    if (declared->size != s.size)
      return corrupt(what + " is " + std::to_string(s.size) + " bytes, but " + who + " declares " +
                     (declared->size ? std::to_string(declared->size) + " bytes" : "a type it cannot size"));
  }
  return {};
}

Result<void> check_pipeline(const Contents& c, const Pipeline& p, const std::vector<spirv::Module>& modules) {
  const std::string pipeline = "pipeline '" + p.name + "'";
  for (uint32_t index : p.shaders) {
    const Shader& shader = c.shaders[index];
    const spirv::Module& module = modules[shader.blob];
    const spirv::EntryPoint* entry =
        module.find(*spirv::execution_model_of_stage(shader.stage), shader.entry_point);
    const std::string who = "shader '" + shader.name + "'";
    for (const spirv::Resource& r : module.resources) {
      if (!module.uses(*entry, r.variable)) continue;
      const std::string slot = "set " + std::to_string(r.set) + ", binding " + std::to_string(r.binding);
      const SetLayout* layout = nullptr;
      if (r.set < p.set_layouts.size() && p.set_layouts[r.set] != kNone)
        layout = &c.set_layouts[p.set_layouts[r.set]];
      // Bindings are sorted by number (checked by decode).
      auto b = layout ? std::lower_bound(layout->bindings.begin(), layout->bindings.end(), r.binding,
                                         [](const Binding& x, uint32_t n) { return x.binding < n; })
                      : std::vector<Binding>::const_iterator{};
      if (layout && b != layout->bindings.end() && b->binding != r.binding) b = layout->bindings.end();
      if (!layout || b == layout->bindings.end())
        return corrupt(pipeline + ": " + who + " uses " + slot + ", which the pipeline's layout lacks");
      const std::string binding = pipeline + ": binding '" + b->name + "' (" + slot + ")";
      if (r.compatible == 0)
        return corrupt(pipeline + ": " + who + " uses " + slot +
                       " as a resource no core descriptor type holds");
      if (!(r.compatible & (1u << b->descriptor_type)))
        return corrupt(binding + " is a " + descriptor_type_name(b->descriptor_type) + " descriptor, but " +
                       who + " declares a " + type_names(r.compatible));
      if (!(b->stage_flags & shader.stage))
        return corrupt(binding + " is not visible to the " + spirv::stage_name(shader.stage) +
                       " stage, which " + who + " uses it from");
      if (r.array_size > b->count)
        return corrupt(binding + " holds " + std::to_string(b->count) + " descriptor(s), but " + who +
                       " declares an array of " + std::to_string(r.array_size));
    }
    if (module.push_constants && module.uses(*entry, module.push_constants->variable)) {
      if (p.push_constant_size == 0 || !(p.push_constant_stages & shader.stage))
        return corrupt(pipeline + ": " + who +
                       " uses push constants, which the pipeline's layout lacks for the " +
                       spirv::stage_name(shader.stage) + " stage");
      if (p.push_constant_size < module.push_constants->size)
        return corrupt(pipeline + ": push constants are " + std::to_string(p.push_constant_size) +
                       " bytes, but " + who + " uses " + std::to_string(module.push_constants->size));
    }
    if (auto ok = check_constants(module, p.constants, shader.stage, pipeline, who); !ok) return ok;
    if (shader.stage == 0x1 && p.kind == PipelineKind::graphics) {
      std::vector<uint32_t> provided;  // attribute locations, sorted for lookups
      for (const auto& a : p.graphics.vertex_attributes) provided.push_back(a.location);
      std::sort(provided.begin(), provided.end());
      for (const spirv::Input& in : module.inputs) {
        if (!module.uses(*entry, in.variable)) continue;
        if (in.locations > kMaxVertexLocations)
          return corrupt(pipeline + ": vertex " + who + " reads " + std::to_string(in.locations) +
                         " locations from one input");
        for (uint64_t location = in.location; location < uint64_t(in.location) + in.locations; ++location) {
          if (!std::binary_search(provided.begin(), provided.end(), location))
            return corrupt(pipeline + ": vertex " + who + " reads input location " +
                           std::to_string(location) + ", which has no vertex attribute");
        }
      }
    }
  }
  return {};
}

// The namespace a resource binds in from the descriptor types it fits, or nullopt for what OpenGL has no
// binding for. A variable that fits a separate sampler, a separate sampled image or an input attachment
// is one (the walker also lets such variables fit a combined descriptor, as Vulkan allows): refused,
// even though it fits a texture too. Otherwise all the types it fits are of one namespace.
std::optional<GlNamespace> gl_namespace_of_mask(spirv::DescriptorTypeMask compatible) {
  constexpr spirv::DescriptorTypeMask kNotInOpenGl = (1u << 0) | (1u << 2) | (1u << 10);
  if (compatible & kNotInOpenGl) return std::nullopt;
  for (uint32_t type = 0; type < 11; ++type)
    if ((compatible >> type) & 1u)
      if (auto kind = gl_namespace_of(type)) return kind;
  return std::nullopt;
}

// The steps the checks of shaders against their pipelines may take: 16 x the archive's SPIR-V size.
uint64_t interface_check_budget(const Contents& c) {
  uint64_t budget = 64;
  for (auto blob : c.spirv) budget += blob.size_bytes();
  return budget * 16;
}

// The SPIR-V capabilities of OpenGL 4.5 core with GL_ARB_gl_spirv (its specification's table) and of
// the GL_ARB extensions glslang's OpenGL client emits for GLSL 4.50 (shader ballot and vote, int64,
// viewport layer array, shader draw parameters).
bool gl_capability(uint32_t capability) {
  static constexpr uint32_t kAllowed[] = {
      0,    1,    2,    3,   10, 11, 21, 25, 27, 28, 29, 30, 31, 32, 33,
      34,   35,   36,   37,                                               // Matrix .. SampledRect
      43,   44,   45,   46,  47, 48, 49, 50, 51, 52, 53, 54, 55, 56, 57,  // Sampled1D .. MultiViewport
      4423, 4427, 4431, 5254};  // SubgroupBallotKHR, DrawParameters, SubgroupVoteKHR, ViewportIndexLayer
  return std::find(std::begin(kAllowed), std::end(kAllowed), capability) != std::end(kAllowed);
}

// A GL pipeline's shaders against its binding table: each stage's entry point exists, every resource it
// uses has a binding of its kind at its number, and there are no push constants (OpenGL has none).
// `work` counts resources checked against `budget` (the pipelines x resources bound, as for Vulkan).
Result<void> check_gl_pipeline(const Contents& c, const GlPipeline& p,
                               std::vector<std::optional<spirv::Module>>& modules, uint64_t& work,
                               uint64_t budget) {
  work += 1 + p.bindings.size();
  for (const GlShader& shader : p.shaders) {
    const std::string who = "OpenGL pipeline '" + p.name + "', shader '" + shader.name + "'";
    if (!modules[shader.blob]) {
      auto module = spirv::walk(c.spirv[shader.blob]);
      if (!module) return corrupt(who + ": " + module.error().message);
      modules[shader.blob] = std::move(module.value());
    }
    const spirv::Module& module = *modules[shader.blob];
    work += 1 + module.resources.size() + p.constants.size();
    if (work > budget)
      return corrupt("checking OpenGL pipeline '" + p.name + "' against its shaders expands beyond " +
                     std::to_string(budget) + " steps (16 x the SPIR-V size): pipelines share huge shaders");
    const auto model = spirv::execution_model_of_stage(shader.stage);
    const spirv::EntryPoint* entry = model ? module.find(*model, shader.entry_point) : nullptr;
    if (!entry)
      return corrupt(who + " has no " + spirv::stage_name(shader.stage) + " entry point named '" +
                     shader.entry_point + "' in its SPIR-V");
    if (module.push_constants && module.uses(*entry, module.push_constants->variable))
      return corrupt(who + " uses push constants, which OpenGL does not have");
    // Only what OpenGL 4.5 with GL_ARB_gl_spirv defines reaches the driver: Mesa's llvmpipe crashes
    // linking a fragment-barycentric module, for one.
    for (uint32_t capability : module.capabilities)
      if (!gl_capability(capability))
        return corrupt(who + " declares SPIR-V capability " + std::to_string(capability) +
                       ", which OpenGL 4.5 with GL_ARB_gl_spirv does not have");
    if (auto ok = check_constants(module, p.constants, shader.stage, "OpenGL pipeline '" + p.name + "'",
                                  "shader '" + shader.name + "'");
        !ok)
      return ok;
    for (const spirv::Resource& r : module.resources) {
      if (!module.uses(*entry, r.variable)) continue;
      const auto kind = gl_namespace_of_mask(r.compatible);
      auto resource = [&] { return who + ": the resource at binding " + std::to_string(r.binding); };
      if (!kind)
        return corrupt(
            resource() +
            " is of a kind OpenGL cannot bind (a separate sampler or image, or a uniform outside a block)");
      // The bindings are sorted by (kind, first binding) without overlaps (validate): the last range
      // starting at or before r.binding is the only one that can hold it.
      auto after =
          std::upper_bound(p.bindings.begin(), p.bindings.end(), std::pair{uint32_t(*kind), r.binding},
                           [](const std::pair<uint32_t, uint32_t>& key, const GlBinding& b) {
                             return key < std::pair{b.kind, b.binding};
                           });
      const GlBinding* bound = after == p.bindings.begin() ? nullptr : &*(after - 1);
      if (!bound || bound->kind != uint32_t(*kind) || r.binding - bound->binding >= bound->count ||
          (bound->stages & shader.stage) == 0)
        return corrupt(resource() + " has no binding of its kind in the pipeline's table");
      if (r.array_size > bound->count - (r.binding - bound->binding))
        return corrupt(resource() + " is an array larger than its binding '" + bound->name + "'");
    }
  }
  return {};
}

}  // namespace

Result<void> check_shader_interfaces(const Contents& c) {
  std::vector<spirv::Module> modules(c.spirv.size());
  std::vector<bool> walked(c.spirv.size());
  for (const Shader& shader : c.shaders) {
    const std::string who = "shader '" + shader.name + "'";
    if (!walked[shader.blob]) {
      auto module = spirv::walk(c.spirv[shader.blob]);
      if (!module) return corrupt(who + ": " + module.error().message);
      modules[shader.blob] = std::move(module.value());
      walked[shader.blob] = true;
    }
    const auto model = spirv::execution_model_of_stage(shader.stage);
    if (!model || !modules[shader.blob].find(*model, shader.entry_point))
      return corrupt(who + " has no " + spirv::stage_name(shader.stage) + " entry point named '" +
                     shader.entry_point + "' in its SPIR-V");
  }
  // Pipelines may share shaders, so the checks below cost pipelines x resources per shader: bounded, like
  // decoding, by the file's own size, so that a small archive cannot make loading take minutes.
  uint64_t work = 0;
  const uint64_t budget = interface_check_budget(c);
  for (const Pipeline& p : c.pipelines) {
    for (uint32_t index : p.shaders) {
      const spirv::Module& m = modules[c.shaders[index].blob];
      work += 1 + m.resources.size() + m.inputs.size() + p.constants.size();
    }
    if (work > budget)
      return corrupt("checking pipeline '" + p.name + "' against its shaders expands beyond " +
                     std::to_string(budget) + " steps (16 x the SPIR-V size): pipelines share huge shaders");
  }
  for (const Pipeline& p : c.pipelines)
    if (auto ok = check_pipeline(c, p, modules); !ok) return ok;
  return {};
}

Result<void> check_gl_shader_interfaces(const Contents& c) {
  // Walked on their own (their blobs are the GL compilations), bounded as the Vulkan pipelines are.
  uint64_t work = 0;
  const uint64_t budget = interface_check_budget(c);
  std::vector<std::optional<spirv::Module>> gl_modules(c.spirv.size());
  for (const GlPipeline& p : c.gl_pipelines) {
    if (auto ok = check_gl_pipeline(c, p, gl_modules, work, budget); !ok) return ok;
  }
  return {};
}

}  // namespace statepack::format
