#include "semantic_check.hpp"

#include "support/failure.hpp"

#include "support/parallel_for.hpp"

#include <algorithm>
#include <array>
#include <iterator>
#include <map>
#include <optional>
#include <span>
#include <unordered_set>

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

using detail::corrupt;

// Names a pipeline and one of its shaders in messages. The strings are built only when a check fails:
// building them for every check cost a load of 100 pipelines a sixth of its own time.
struct Naming {
  const char* kind;  // "pipeline" or "OpenGL pipeline"
  const std::string& pipeline_name;
  const std::string& shader_name;
  [[gnu::cold]] std::string pipeline() const { return std::string(kind) + " '" + pipeline_name + "'"; }
  [[gnu::cold]] std::string shader() const { return "shader '" + shader_name + "'"; }
};

// The constants of one stage against its module: each declared, with the same size. A Vulkan map entry
// must match the size of the constant the shader declares (VUID-VkSpecializationMapEntry-constantID-00776);
// one the shader does not declare is harmless to Vulkan but a mistake of the archive, and an error for
// glSpecializeShader. `n` names the pipeline and the shader in messages.
Result<void> check_constants(const spirv::Module& module, const std::vector<SpecConstant>& constants,
                             uint32_t stage, const Naming& n) {
  for (const SpecConstant& s : constants) {
    if (s.stage != stage) continue;
    const spirv::SpecConstant* declared = module.find_spec_constant(s.constant_id);
    auto what = [&] {
      return n.pipeline() + ": specialization constant '" + s.name + "' (id " +
             std::to_string(s.constant_id) + ")";
    };
    if (!declared) return corrupt(what() + " is not declared by " + n.shader());
    if (declared->size != s.size)
      return corrupt(what() + " is " + std::to_string(s.size) + " bytes, but " + n.shader() + " declares " +
                     (declared->size ? std::to_string(declared->size) + " bytes" : "a type it cannot size"));
  }
  return {};
}

// Keys of 32-bit words, for the sets of checks already made: a list, or a fixed array (a set's resources
// against a layout), so that looking one up allocates nothing.
struct WordsHash {
  template <class Words>
  size_t operator()(const Words& key) const {
    uint64_t h = 14695981039346656037ull;  // FNV-1a over the words
    for (uint32_t w : key) h = (h ^ w) * 1099511628211ull;
    return size_t(h);
  }
};
using Key = std::vector<uint32_t>;
using KeySet = std::unordered_set<Key, WordsHash>;
// (blob, entry point, stage, set, layout): shader records that name the same entry point of the same blob
// for the same stage use the same resources, so they pass or fail against a layout alike.
using SetCheck = std::array<uint32_t, 5>;

// What one entry point of a module uses: its descriptors by set number (in module order within a set)
// and (for a vertex shader) its inputs.
struct EntryUse {
  std::map<uint32_t, std::vector<const spirv::Resource*>> resources;
  std::vector<const spirv::Input*> inputs;
  const spirv::Resource* input_attachment = nullptr;  // the first subpass input it reads, if any
};

// The steps the shader checks may take: 16 x what the archive holds (its SPIR-V, its layouts'
// bindings, its pipelines' records). Each distinct check is made once (InterfaceChecks), so a valid
// archive needs far less than this however many pipelines share a shader or a layout; the budget stops
// only a small archive that would make loading take minutes.
uint64_t interface_check_budget(const Contents& c) {
  uint64_t size = 64;
  for (auto blob : c.spirv) size += blob.size_bytes();
  for (const SetLayout& l : c.set_layouts) size += 1 + l.bindings.size();
  for (const Pipeline& p : c.pipelines)
    size += 1 + p.shaders.size() + p.set_layouts.size() + p.constants.size() +
            p.graphics.vertex_attributes.size();
  for (const GlPipeline& p : c.gl_pipelines)
    size += 1 + p.shaders.size() + p.bindings.size() + p.constants.size();
  return size * 16;
}

// The Vulkan pipelines' checks against their shaders, each distinct one made once: pipelines that share
// a shader and what it is checked against (one set's layout, the vertex attributes) pass or fail alike,
// so 100,000 pipelines over one shader and one layout cost one check, and layouts combined in many ways
// cost one check per (shader, set, layout). Push constants and
// specialization constants are checked for every pipeline (their cost is the pipeline's own record).
class InterfaceChecks {
 public:
  InterfaceChecks(const Contents& c, const std::vector<spirv::Module>& modules)
      : c_(c), modules_(modules), budget_(interface_check_budget(c)) {}

  Result<void> check(const Pipeline& p) {
    for (uint32_t index : p.shaders) {
      const Shader& shader = c_.shaders[index];
      const spirv::Module& module = modules_[shader.blob];
      const spirv::EntryPoint* entry =
          module.find(*spirv::execution_model_of_stage(shader.stage), shader.entry_point);
      const Naming n{"pipeline", p.name, shader.name};
      const EntryUse* use = uses(shader.blob, module, *entry);
      if (!use) return over_budget(p);
      for (const auto& [set, resources] : use->resources) {
        const uint32_t layout = set < p.set_layouts.size() ? p.set_layouts[set] : kNone;
        const SetCheck key = {shader.blob, entry_index(module, *entry), shader.stage, set, layout};
        if (resources_checked_.count(key)) continue;
        if (!charge(resources.size())) return over_budget(p);
        if (auto ok = check_resources(shader, layout, resources, n); !ok) return ok;
        resources_checked_.insert(key);
      }
      // Dynamic rendering has no input attachments (VUID-VkGraphicsPipelineCreateInfo-renderPass-06061).
      if (use->input_attachment && p.kind == PipelineKind::graphics && p.render_pass == kNone)
        return corrupt(
            n.pipeline() + ": " + n.shader() + " reads an input attachment (set " +
            std::to_string(use->input_attachment->set) + ", binding " +
            std::to_string(use->input_attachment->binding) +
            "), but the pipeline has no render pass, and dynamic rendering has no input attachments");
      if (module.push_constants && module.uses(*entry, module.push_constants->variable)) {
        if (p.push_constant_size == 0 || !(p.push_constant_stages & shader.stage))
          return corrupt(n.pipeline() + ": " + n.shader() +
                         " uses push constants, which the pipeline's layout lacks for the " +
                         spirv::stage_name(shader.stage) + " stage");
        if (p.push_constant_size < module.push_constants->size)
          return corrupt(n.pipeline() + ": push constants are " + std::to_string(p.push_constant_size) +
                         " bytes, but " + n.shader() + " uses " +
                         std::to_string(module.push_constants->size));
      }
      if (auto ok = check_constants(module, p.constants, shader.stage, n); !ok) return ok;
      if (shader.stage == 0x1 && p.kind == PipelineKind::graphics)
        if (auto ok = check_vertex_inputs(p, index, *use, n); !ok) return ok;
    }
    return {};
  }

 private:
  bool charge(uint64_t steps) {
    work_ += 1 + steps;
    return work_ <= budget_;
  }
  Error over_budget(const Pipeline& p) const {
    return corrupt("checking pipeline '" + p.name + "' against its shaders expands beyond " +
                   std::to_string(budget_) +
                   " steps (16 x the archive's size): pipelines share huge shaders");
  }

  // What the entry point uses, found once per (module, entry point); null when the budget is spent.
  const EntryUse* uses(uint32_t blob, const spirv::Module& module, const spirv::EntryPoint& entry) {
    auto [it, fresh] = uses_.try_emplace({blob, entry_index(module, entry)});
    if (!fresh) return &it->second;
    if (!charge(module.resources.size() + module.inputs.size())) return nullptr;
    for (const spirv::Resource& r : module.resources)
      if (module.uses(entry, r.variable)) {
        it->second.resources[r.set].push_back(&r);
        if (r.compatible == 1u << 10 /* VK_DESCRIPTOR_TYPE_INPUT_ATTACHMENT */ &&
            !it->second.input_attachment)
          it->second.input_attachment = &r;
      }
    for (const spirv::Input& in : module.inputs)
      if (module.uses(entry, in.variable)) it->second.inputs.push_back(&in);
    return &it->second;
  }

  // The resources a shader uses in one set against the set's layout (`layout_index`: kNone for none).
  Result<void> check_resources(const Shader& shader, uint32_t layout_index,
                               const std::vector<const spirv::Resource*>& resources, const Naming& n) const {
    const SetLayout* layout = layout_index != kNone ? &c_.set_layouts[layout_index] : nullptr;
    for (const spirv::Resource* r : resources) {
      auto slot = [&] { return "set " + std::to_string(r->set) + ", binding " + std::to_string(r->binding); };
      // Bindings are sorted by number (checked by decode).
      auto b = layout ? std::lower_bound(layout->bindings.begin(), layout->bindings.end(), r->binding,
                                         [](const Binding& x, uint32_t number) { return x.binding < number; })
                      : std::vector<Binding>::const_iterator{};
      if (layout && b != layout->bindings.end() && b->binding != r->binding) b = layout->bindings.end();
      if (!layout || b == layout->bindings.end())
        return corrupt(n.pipeline() + ": " + n.shader() + " uses " + slot() +
                       ", which the pipeline's layout lacks");
      auto binding = [&] { return n.pipeline() + ": binding '" + b->name + "' (" + slot() + ")"; };
      if (r->compatible == 0)
        return corrupt(n.pipeline() + ": " + n.shader() + " uses " + slot() +
                       " as a resource no core descriptor type holds");
      if (!(r->compatible & (1u << b->descriptor_type)))
        return corrupt(binding() + " is a " + descriptor_type_name(b->descriptor_type) + " descriptor, but " +
                       n.shader() + " declares a " + type_names(r->compatible));
      if (!(b->stage_flags & shader.stage))
        return corrupt(binding() + " is not visible to the " + spirv::stage_name(shader.stage) +
                       " stage, which " + n.shader() + " uses it from");
      if (r->array_size > b->count)
        return corrupt(binding() + " holds " + std::to_string(b->count) + " descriptor(s), but " +
                       n.shader() + " declares an array of " + std::to_string(r->array_size));
    }
    return {};
  }

  Result<void> check_vertex_inputs(const Pipeline& p, uint32_t shader_index, const EntryUse& use,
                                   const Naming& n) {
    // The key: the attribute locations, sorted (looked up below), then the shader index.
    Key key;
    key.reserve(p.graphics.vertex_attributes.size() + 1);
    for (const auto& a : p.graphics.vertex_attributes) key.push_back(a.location);
    std::sort(key.begin(), key.end());
    key.push_back(shader_index);
    if (inputs_checked_.count(key)) return {};
    const auto provided = std::span(key).first(key.size() - 1);
    if (!charge(use.inputs.size())) return over_budget(p);
    for (const spirv::Input* in : use.inputs) {
      if (in->locations > kMaxVertexLocations)
        return corrupt(n.pipeline() + ": vertex " + n.shader() + " reads " + std::to_string(in->locations) +
                       " locations from one input");
      for (uint64_t location = in->location; location < uint64_t(in->location) + in->locations; ++location)
        if (!std::binary_search(provided.begin(), provided.end(), location))
          return corrupt(n.pipeline() + ": vertex " + n.shader() + " reads input location " +
                         std::to_string(location) + ", which has no vertex attribute");
    }
    inputs_checked_.insert(std::move(key));
    return {};
  }

  const Contents& c_;
  const std::vector<spirv::Module>& modules_;
  const uint64_t budget_;
  uint64_t work_ = 0;
  // By (blob, entry point): an entry point, not its function, says what it uses (from SPIR-V 1.4 on, two
  // OpEntryPoints may name one function with different interfaces).
  std::map<std::pair<uint32_t, uint32_t>, EntryUse> uses_;
  static uint32_t entry_index(const spirv::Module& module, const spirv::EntryPoint& entry) {
    return static_cast<uint32_t>(&entry - module.entry_points.data());
  }
  std::unordered_set<SetCheck, WordsHash> resources_checked_;  // those that passed
  KeySet inputs_checked_;  // (attribute locations, shader index) that passed
};

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
// `work` counts steps against `budget` (interface_check_budget). As for Vulkan, each distinct check is
// made once: `checked` holds the (module, stage, entry point, binding table) of every shader that passed;
// only the specialization constants, the pipeline's own record, are checked for every pipeline.
Result<void> check_gl_pipeline(const Contents& c, const GlPipeline& p,
                               std::vector<std::optional<spirv::Module>>& modules, uint64_t& work,
                               uint64_t budget, std::unordered_set<std::string>& checked) {
  work += 1 + p.bindings.size();
  std::string table;  // the binding table as words, the part of the key all stages share
  for (const GlBinding& b : p.bindings)
    for (uint32_t w : {b.kind, b.binding, b.count, b.stages})
      table.append(reinterpret_cast<const char*>(&w), 4);
  for (const GlShader& shader : p.shaders) {
    auto who = [&] { return "OpenGL pipeline '" + p.name + "', shader '" + shader.name + "'"; };
    if (!modules[shader.blob]) {
      auto module = spirv::walk(c.spirv[shader.blob]);
      if (!module) return corrupt(who() + ": " + module.error().message);
      modules[shader.blob] = std::move(module.value());
    }
    const spirv::Module& module = *modules[shader.blob];
    if (auto ok = check_constants(module, p.constants, shader.stage,
                                  Naming{"OpenGL pipeline", p.name, shader.name});
        !ok)
      return ok;
    std::string key = table;  // (binding table, module, stage, entry point)
    for (uint32_t w : {shader.blob, shader.stage}) key.append(reinterpret_cast<const char*>(&w), 4);
    key += shader.entry_point;
    if (checked.count(key)) continue;
    work += 1 + module.entry_points.size() + module.capabilities.size() + module.resources.size();
    if (work > budget)
      return corrupt("checking OpenGL pipeline '" + p.name + "' against its shaders expands beyond " +
                     std::to_string(budget) +
                     " steps (16 x the archive's size): pipelines share huge shaders");
    const auto model = spirv::execution_model_of_stage(shader.stage);
    const spirv::EntryPoint* entry = model ? module.find(*model, shader.entry_point) : nullptr;
    if (!entry)
      return corrupt(who() + " has no " + spirv::stage_name(shader.stage) + " entry point named '" +
                     shader.entry_point + "' in its SPIR-V");
    if (module.push_constants && module.uses(*entry, module.push_constants->variable))
      return corrupt(who() + " uses push constants, which OpenGL does not have");
    // Only what OpenGL 4.5 with GL_ARB_gl_spirv defines reaches the driver: Mesa's llvmpipe crashes
    // linking a fragment-barycentric module, for one.
    for (uint32_t capability : module.capabilities)
      if (!gl_capability(capability))
        return corrupt(who() + " declares SPIR-V capability " + std::to_string(capability) +
                       ", which OpenGL 4.5 with GL_ARB_gl_spirv does not have");
    for (const spirv::Resource& r : module.resources) {
      if (!module.uses(*entry, r.variable)) continue;
      const auto kind = gl_namespace_of_mask(r.compatible);
      auto resource = [&] { return who() + ": the resource at binding " + std::to_string(r.binding); };
      if (!kind)
        return corrupt(
            resource() +
            " is of a kind OpenGL cannot bind (a separate sampler or image, or a uniform outside a block)");
      // The bindings are sorted by (kind, first binding) without overlaps (validate): the last range
      // starting at or before r.binding is the only one that can hold it.
      auto after =
          std::upper_bound(p.bindings.begin(), p.bindings.end(), std::pair{uint32_t(*kind), r.binding},
                           [](const std::pair<uint32_t, uint32_t>& wanted, const GlBinding& b) {
                             return wanted < std::pair{b.kind, b.binding};
                           });
      const GlBinding* bound = after == p.bindings.begin() ? nullptr : &*(after - 1);
      if (!bound || bound->kind != uint32_t(*kind) || r.binding - bound->binding >= bound->count ||
          (bound->stages & shader.stage) == 0)
        return corrupt(resource() + " has no binding of its kind in the pipeline's table");
      if (r.array_size > bound->count - (r.binding - bound->binding))
        return corrupt(resource() + " is an array larger than its binding '" + bound->name + "'");
    }
    checked.insert(std::move(key));
  }
  return {};
}

}  // namespace

Result<void> check_shader_interfaces(const Contents& c, uint32_t threads,
                                     std::vector<spirv::Module>* walked) {
  // Each blob a shader uses, walked once (on `threads` threads: the walks are independent); an error is
  // reported at the first shader that uses the blob, whichever thread found it.
  std::vector<uint32_t> used;
  std::vector<bool> is_used(c.spirv.size());
  for (const Shader& shader : c.shaders)
    if (!is_used[shader.blob]) is_used[shader.blob] = true, used.push_back(shader.blob);
  std::vector<std::optional<Result<spirv::Module>>> walks(c.spirv.size());
  detail::parallel_for(used.size(), threads,
                       [&](size_t i) { walks[used[i]] = spirv::walk(c.spirv[used[i]]); });
  std::vector<spirv::Module> modules(c.spirv.size());
  for (const Shader& shader : c.shaders) {
    auto who = [&] { return "shader '" + shader.name + "'"; };
    if (auto& walk = walks[shader.blob]) {
      if (!*walk) return corrupt(who() + ": " + walk->error().message);
      modules[shader.blob] = std::move(walk->value());
      walk.reset();
    }
    const auto model = spirv::execution_model_of_stage(shader.stage);
    if (!model || !modules[shader.blob].find(*model, shader.entry_point))
      return corrupt(who() + " has no " + spirv::stage_name(shader.stage) + " entry point named '" +
                     shader.entry_point + "' in its SPIR-V");
  }
  {
    InterfaceChecks checks(c, modules);
    for (const Pipeline& p : c.pipelines)
      if (auto ok = checks.check(p); !ok) return ok;
  }
  if (walked) *walked = std::move(modules);
  return {};
}

Result<void> check_gl_shader_interfaces(const Contents& c) {
  // Walked on their own (their blobs are the GL compilations), bounded as the Vulkan pipelines are.
  uint64_t work = 0;
  const uint64_t budget = interface_check_budget(c);
  std::vector<std::optional<spirv::Module>> gl_modules(c.spirv.size());
  std::unordered_set<std::string> checked;
  for (const GlPipeline& p : c.gl_pipelines) {
    if (auto ok = check_gl_pipeline(c, p, gl_modules, work, budget, checked); !ok) return ok;
  }
  return {};
}

}  // namespace statepack::format
