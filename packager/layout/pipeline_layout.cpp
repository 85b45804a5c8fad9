#include "pipeline_layout.hpp"

#include <vulkan/vulkan_core.h>

#include <map>
#include <set>

#include "block_views.hpp"
#include "inline_constants.hpp"
#include "interface_check.hpp"
#include "notation/enum_tables.hpp"
#include "support/suggest.hpp"

namespace statepack::packager {
namespace {

// Vulkan's name of the descriptor type, with the notation's resource type where one maps to it.
std::string descriptor_name(uint32_t type) {
  std::string name = format::descriptor_type_name(type);
  switch (type) {
    case VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE:
      return name + " (TEXTURE_SRV)";
    case VK_DESCRIPTOR_TYPE_STORAGE_IMAGE:
      return name + " (TEXTURE_UAV)";
    case VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER:
      return name + " (CONSTANT_BUFFER)";
    case VK_DESCRIPTOR_TYPE_STORAGE_BUFFER:
      return name + " (BUFFER_SRV/BUFFER_UAV)";
  }
  return name;
}

std::string where_text(const PipelineDesc& p, const StageInput& stage) {
  return "pipeline '" + p.name + "', shader '" + stage.desc->name + "'";
}

bool takes_sampler(uint32_t type) {
  return type == VK_DESCRIPTOR_TYPE_SAMPLER || type == VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
}

// One resource of the final layout and every reflected use of it, for patching.
struct Slot {
  format::Binding binding;
  uint32_t set = 0;
  bool combined_attribute = false;  // [[vk::combinedImageSampler]] on its variable
  std::string sampler_name;         // the sampler paired into this combined binding, if any
};

void patch(std::vector<uint32_t>& words, const ReflectedBinding& r, uint32_t set, uint32_t binding) {
  words[r.set_word] = set;
  words[r.binding_word] = binding;
}

// Immutable samplers attach to the binding named SamplerOrTextureName (or that name plus the combined
// sampler suffix); false when no sampler-taking binding has that name.
bool attach_sampler(std::vector<Slot*>& candidates, const ImmutableSamplerDesc& s, const std::string& suffix,
                    ContentsBuilder& builder) {
  for (Slot* slot : candidates) {
    if (!takes_sampler(slot->binding.descriptor_type)) continue;
    if (slot->binding.name != s.name && slot->sampler_name != s.name &&
        (suffix.empty() || slot->binding.name != s.name + suffix))
      continue;
    slot->binding.immutable_sampler = builder.add_sampler(s.sampler);
    return true;
  }
  return false;
}

bool check_stage_use(const PipelineDesc& p, const StageInput& stage, const ReflectedBinding& r,
                     uint32_t declared_type, uint32_t declared_count, uint32_t declared_stages,
                     Diagnostics& diag) {
  if (declared_type != r.descriptor_type) {
    diag.error(p.where, where_text(p, stage) + ": resource '" + r.name + "' is a " +
                            descriptor_name(r.descriptor_type) + " in the shader but a " +
                            descriptor_name(declared_type) + " in the layout");
    return false;
  }
  if (r.count > declared_count) {
    diag.error(p.where, where_text(p, stage) + ": resource '" + r.name + "' is an array of " +
                            std::to_string(r.count) + " in the shader but of " +
                            std::to_string(declared_count) + " in the layout");
    return false;
  }
  if (declared_stages != 0 && (declared_stages & r.stage) == 0) {
    diag.error(p.where, where_text(p, stage) + ": resource '" + r.name +
                            "' is used in a stage its ShaderStages do not include");
    return false;
  }
  return true;
}

bool layout_from_signatures(const PipelineDesc& p, const std::vector<StageInput>& stages,
                            const Notation& notation, ContentsBuilder& builder, PipelineLayout& out,
                            Diagnostics& diag) {
  std::map<uint32_t, const SignatureDesc*> by_set;
  for (const auto& name : p.signatures) {
    const SignatureDesc* sig = nullptr;
    for (const auto& s : notation.signatures)
      if (s.name == name) sig = &s;
    if (!sig) return false;  // reported by resolve_references
    auto [it, inserted] = by_set.emplace(sig->binding_index, sig);
    if (!inserted) {
      diag.error(p.where, "pipeline '" + p.name + "': resource signatures '" + it->second->name + "' and '" +
                              name + "' both use BindingIndex " + std::to_string(sig->binding_index));
      return false;
    }
  }
  uint32_t set_count = by_set.empty() ? 0 : by_set.rbegin()->first + 1;
  out.set_layouts.assign(set_count, format::kNone);
  for (const auto& [set, sig] : by_set)
    out.set_layouts[set] = builder.add_set_layout(
        signature_set_layout(*sig, !notation.ignored_signatures.count(sig->name), builder));

  bool ok = true;
  std::vector<std::string> all_names;
  for (const auto& [set, sig] : by_set)
    for (const auto& r : sig->resources) all_names.push_back(r.name);
  for (size_t s = 0; s < stages.size(); ++s) {
    for (const ReflectedBinding& r : stages[s].reflection->bindings) {
      bool found = false;
      for (const auto& [set, sig] : by_set) {
        const format::SetLayout& layout = builder.contents.set_layouts[out.set_layouts[set]];
        for (const format::Binding& b : layout.bindings) {
          if (b.name != r.name) continue;
          found = true;
          ok &= check_stage_use(p, stages[s], r, b.descriptor_type, b.count, b.stage_flags, diag);
          patch(out.patched_spirv[s], r, set, b.binding);
        }
        if (found) break;
      }
      if (!found) {
        diag.error(p.where, where_text(p, stages[s]) + ": resource '" + r.name +
                                "' is in none of the pipeline's resource signatures" +
                                detail::did_you_mean(r.name, all_names));
        ok = false;
      }
    }
  }
  return ok;
}

// Where an error about resource `name` belongs: the ResourceLayout variable naming it, else `fallback`.
Location variable_location(const PipelineDesc& p, const std::string& name, const SourceTexts& sources,
                           const Location& fallback) {
  for (const ResourceVariable& v : p.variables)
    if (v.name == name) return sources.at(p.where, v.pointer);
  return fallback;
}

// [[vk::combinedImageSampler]] on a texture and a sampler at the same set and binding: one combined
// image sampler descriptor, named after the texture, that both variables read (Vulkan allows a
// separate image and a sampler variable on a combined descriptor). Without the attribute, or without
// a partner, they stay apart and the collision moves one of them, as for HLSL's t0 and s0.
void pair_combined_image_samplers(std::vector<Slot>& slots, std::map<std::string, size_t>& by_name) {
  constexpr size_t kKept = SIZE_MAX;
  std::vector<size_t> absorbed_by(slots.size(), kKept);  // a sampler's texture slot, once paired
  for (size_t i = 0; i < slots.size(); ++i) {
    Slot& texture = slots[i];
    if (!texture.combined_attribute || texture.binding.descriptor_type != VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE)
      continue;
    for (size_t j = 0; j < slots.size(); ++j) {
      const Slot& sampler = slots[j];
      if (absorbed_by[j] != kKept || !sampler.combined_attribute ||
          sampler.binding.descriptor_type != VK_DESCRIPTOR_TYPE_SAMPLER || sampler.set != texture.set ||
          sampler.binding.binding != texture.binding.binding ||
          sampler.binding.count != texture.binding.count)
        continue;
      texture.binding.descriptor_type = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
      texture.binding.stage_flags |= sampler.binding.stage_flags;
      texture.sampler_name = sampler.binding.name;
      absorbed_by[j] = i;
      break;
    }
  }
  std::vector<Slot> kept;
  std::vector<size_t> new_index(slots.size());
  for (size_t i = 0; i < slots.size(); ++i)
    if (absorbed_by[i] == kKept) new_index[i] = kept.size(), kept.push_back(std::move(slots[i]));
  for (auto& [name, index] : by_name)  // a paired sampler's name leads to its texture's binding
    index = new_index[absorbed_by[index] == kKept ? index : absorbed_by[index]];
  slots = std::move(kept);
}

// ResourceLayout variables and immutable samplers (attached here) against what the shaders use; false
// when a mismatch is an error (--strict).
bool check_layout_names(const PipelineDesc& p, std::vector<Slot>& slots,
                        const std::map<std::string, size_t>& by_name, ContentsBuilder& builder,
                        const SourceTexts& sources, const LayoutOptions& options, const std::string& pushed,
                        Diagnostics& diag) {
  bool ok = true;
  // ResourceLayout variables and immutable samplers that name nothing the shaders use are warnings, as
  // in Diligent (which ignores them; IGNORE_MISSING_* silences the warning), or errors with --strict: a
  // typo, or a resource used only under a macro the pipeline does not define (Diligent's Tutorial29).
  auto mismatch = [&](const Location& where, const std::string& message, const char* flag) {
    if (options.strict) {
      diag.error(where, message + " (an error with --strict)");
      ok = false;
    } else {
      diag.warning(where, message + " (" + flag + " in the pipeline's Flags silences this)");
    }
  };

  std::vector<std::string> names;
  for (const Slot& slot : slots) names.push_back(slot.binding.name);
  for (const ResourceVariable& v : p.variables) {
    if (p.flags & kIgnoreMissingVariables) break;
    if (v.name == pushed) continue;  // push constants now (inline_constants.hpp checks their use)
    auto it = by_name.find(v.name);
    if (it == by_name.end())
      mismatch(sources.at(p.where, v.pointer),
               "pipeline '" + p.name + "': ResourceLayout variable '" + v.name +
                   "' is not used by any of its shaders" + detail::did_you_mean(v.name, names),
               "IGNORE_MISSING_VARIABLES");
    else if (v.stages != 0 && (slots[it->second].binding.stage_flags & v.stages) == 0)
      mismatch(sources.at(p.where, v.pointer),
               "pipeline '" + p.name + "': ResourceLayout variable '" + v.name +
                   "' is declared for stages its shaders do not use it in",
               "IGNORE_MISSING_VARIABLES");
  }
  std::vector<Slot*> candidates;
  for (Slot& slot : slots) candidates.push_back(&slot);
  for (size_t i = 0; i < p.immutable_samplers.size(); ++i) {
    const ImmutableSamplerDesc& s = p.immutable_samplers[i];
    if (attach_sampler(candidates, s, p.combined_sampler_suffix, builder) ||
        (p.flags & kIgnoreMissingImmutableSamplers))
      continue;
    mismatch(i < p.immutable_sampler_pointers.size() ? sources.at(p.where, p.immutable_sampler_pointers[i])
                                                     : p.where,
             "pipeline '" + p.name + "': immutable sampler '" + s.name +
                 "' matches no sampler or combined texture of its shaders" +
                 (p.combined_sampler_suffix.empty() && by_name.count(s.name + "_sampler")
                      ? " ('" + s.name +
                            "_sampler' would match if the shaders' Desc said "
                            "\"UseCombinedTextureSamplers\": true)"
                      : std::string()) +
                 detail::did_you_mean(s.name, names),
             "IGNORE_MISSING_IMMUTABLE_SAMPLERS");
  }
  return ok;
}

// Stages that declare one block name with members that conflict, or at other slots: statepack, as
// Diligent, merges resources by name, so they read one buffer. Often right (a block each stage declares
// in part), sometimes two buffers that happen to share a name: a warning says which.
void warn_conflicting_views(const PipelineDesc& p, const std::vector<StageInput>& stages,
                            const std::string& pushed, Diagnostics& diag) {
  std::map<std::string, std::vector<std::pair<const StageInput*, const ReflectedBinding*>>> blocks;
  for (const StageInput& stage : stages)
    for (const ReflectedBinding& r : stage.reflection->bindings)
      if (!r.block_layout.empty() && r.name != pushed) blocks[r.name].push_back({&stage, &r});
  for (const auto& [name, uses] : blocks) {
    if (uses.size() < 2) continue;
    const ReflectedBinding& first = *uses.front().second;
    const bool same_layout = std::all_of(uses.begin(), uses.end(), [&](const auto& u) {
      return u.second->block_layout == first.block_layout;
    });
    if (same_layout) continue;
    std::vector<std::vector<uint32_t>> copies;
    for (const auto& [stage, r] : uses) copies.push_back(*stage->spirv);
    std::vector<BlockView> views;
    for (size_t i = 0; i < uses.size(); ++i)
      views.push_back({&copies[i], uses[i].second->variable, stage_text(*uses[i].first->desc)});
    std::string reason = block_views_conflict(views);
    const auto other_slot = std::find_if(uses.begin(), uses.end(), [&](const auto& u) {
      return u.second->set != first.set || u.second->binding != first.binding;
    });
    if (reason.empty() && other_slot != uses.end())
      reason = views.front().shader + " declares it at set " + std::to_string(first.set) + ", binding " +
               std::to_string(first.binding) + " and " + stage_text(*other_slot->first->desc) + " at set " +
               std::to_string(other_slot->second->set) + ", binding " +
               std::to_string(other_slot->second->binding);
    if (reason.empty()) continue;
    diag.warning(p.where,
                 "pipeline '" + p.name + "': its stages declare block '" + name + "' differently (" + reason +
                     "); resources are merged by name, as in Diligent, so they read one buffer: if they "
                     "are two buffers, give them two names");
  }
}

bool implicit_layout(const PipelineDesc& p, const std::vector<StageInput>& stages, ContentsBuilder& builder,
                     const SourceTexts& sources, const LayoutOptions& options, const std::string& pushed,
                     PipelineLayout& out, Diagnostics& diag) {
  // Merge uses by name across stages; the first use decides type and wished-for slot. Inline constants
  // (`pushed`) take no descriptor: they become push constants.
  std::vector<Slot> slots;
  std::map<std::string, size_t> by_name;
  bool ok = true;
  for (const StageInput& stage : stages) {
    for (const ReflectedBinding& r : stage.reflection->bindings) {
      if (r.name == pushed) continue;
      auto [it, inserted] = by_name.emplace(r.name, slots.size());
      if (inserted) {
        slots.push_back({format::Binding{r.name, r.binding, r.descriptor_type, r.count, r.stage}, r.set,
                         r.combined_attribute});
        continue;
      }
      Slot& slot = slots[it->second];
      slot.combined_attribute = slot.combined_attribute || r.combined_attribute;
      if (slot.binding.descriptor_type != r.descriptor_type || slot.binding.count != r.count) {
        diag.error(variable_location(p, r.name, sources, stage.desc->where),
                   where_text(p, stage) + ": resource '" + r.name + "' is declared as a " +
                       descriptor_name(r.descriptor_type) + " of " + std::to_string(r.count) +
                       ", but another stage declares it as a " +
                       descriptor_name(slot.binding.descriptor_type) + " of " +
                       std::to_string(slot.binding.count));
        ok = false;
      }
      slot.binding.stage_flags |= r.stage;
    }
  }
  warn_conflicting_views(p, stages, pushed, diag);
  pair_combined_image_samplers(slots, by_name);
  // Keep each resource's own set and binding where free; move the rest (e.g. HLSL b0 and t0, which
  // glslang both maps to binding 0) to the next free binding of the set.
  std::set<std::pair<uint32_t, uint32_t>> taken;
  for (Slot& slot : slots) {
    auto wanted = std::pair{slot.set, slot.binding.binding};
    if (!taken.count(wanted)) {
      taken.insert(wanted);
      continue;
    }
    if (p.flags & kDontRemapShaderResources) {
      diag.error(p.where, "pipeline '" + p.name + "': resource '" + slot.binding.name + "' shares set " +
                              std::to_string(slot.set) + ", binding " + std::to_string(slot.binding.binding) +
                              " with another resource, and DONT_REMAP_SHADER_RESOURCES forbids moving it");
      ok = false;
      continue;
    }
    uint32_t binding = 0;
    while (taken.count({slot.set, binding})) ++binding;
    slot.binding.binding = binding;
    taken.insert({slot.set, binding});
  }
  ok = check_layout_names(p, slots, by_name, builder, sources, options, pushed, diag) && ok;
  if (!ok) return false;

  uint32_t set_count = 0;
  for (const Slot& slot : slots) set_count = std::max(set_count, slot.set + 1);
  out.set_layouts.assign(set_count, format::kNone);
  for (uint32_t set = 0; set < set_count; ++set) {
    format::SetLayout layout;
    for (const Slot& slot : slots)
      if (slot.set == set) layout.bindings.push_back(slot.binding);
    if (layout.bindings.empty()) continue;
    std::sort(layout.bindings.begin(), layout.bindings.end(),
              [](const format::Binding& a, const format::Binding& b) { return a.binding < b.binding; });
    out.set_layouts[set] = builder.add_set_layout(layout);
  }
  for (size_t s = 0; s < stages.size(); ++s)
    for (const ReflectedBinding& r : stages[s].reflection->bindings) {
      if (r.name == pushed) continue;
      const Slot& slot = slots[by_name[r.name]];
      patch(out.patched_spirv[s], r, slot.set, slot.binding.binding);
    }
  return true;
}

}  // namespace

format::SetLayout signature_set_layout(const SignatureDesc& signature, bool named, ContentsBuilder& builder) {
  format::SetLayout layout;
  layout.name = named ? signature.name : "";
  layout.binding_index = signature.binding_index;
  std::vector<Slot> slots;
  uint32_t all_stages = 0;
  for (uint32_t i = 0; i < signature.resources.size(); ++i) {
    const SignatureResource& r = signature.resources[i];
    slots.push_back(
        {format::Binding{r.name, i, r.descriptor_type, r.array_size, r.stages}, signature.binding_index});
    all_stages |= r.stages;
  }
  std::vector<Slot*> candidates;
  for (Slot& slot : slots) candidates.push_back(&slot);
  std::vector<Slot> extra;
  for (const ImmutableSamplerDesc& s : signature.immutable_samplers) {
    if (attach_sampler(candidates, s, signature.combined_sampler_suffix, builder)) continue;
    // A sampler the shaders declare but Resources do not list: it gets a binding of its own. Named after
    // a texture of a combined-sampler signature, it is that texture's sampler (the suffixed name).
    std::string name = s.name;
    for (const SignatureResource& r : signature.resources)
      if (r.name == s.name && r.descriptor_type == VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE)
        name = s.name + signature.combined_sampler_suffix;
    uint32_t binding = static_cast<uint32_t>(slots.size() + extra.size());
    extra.push_back({format::Binding{name, binding, VK_DESCRIPTOR_TYPE_SAMPLER, 1,
                                     s.stages ? s.stages : all_stages, builder.add_sampler(s.sampler)},
                     signature.binding_index});
  }
  for (const Slot& slot : slots) layout.bindings.push_back(slot.binding);
  for (const Slot& slot : extra) layout.bindings.push_back(slot.binding);
  return layout;
}

bool build_pipeline_layout(const PipelineDesc& pipeline, const std::vector<StageInput>& stages,
                           const Notation& notation, ContentsBuilder& builder, const LayoutOptions& options,
                           PipelineLayout& out, Diagnostics& diag) {
  const InlineConstants pushed = pushed_inline_constants(pipeline, notation);
  out.patched_spirv.clear();
  for (const StageInput& stage : stages) {
    out.patched_spirv.push_back(*stage.spirv);
    for (const ReflectedBinding& r : stage.reflection->bindings) {
      if (r.set_word == 0 || r.binding_word == 0 || r.set_word >= stage.spirv->size() ||
          r.binding_word >= stage.spirv->size()) {
        diag.error(pipeline.where, where_text(pipeline, stage) + ": resource '" + r.name +
                                       "' has no DescriptorSet/Binding decoration to patch");
        return false;
      }
      if (r.count == 0) {
        diag.error(pipeline.where, where_text(pipeline, stage) + ": resource '" + r.name +
                                       "' is a runtime-sized array, which is not supported yet");
        return false;
      }
    }
    out.push_constant_size = std::max(out.push_constant_size, stage.reflection->push_constant_size);
    if (stage.reflection->push_constant_size > 0) out.push_constant_stages |= stage.desc->stage;
  }
  if (!pipeline.signatures.empty()) {
    if (!pipeline.variables.empty() || !pipeline.immutable_samplers.empty()) {
      // Diligent refuses such a pipeline at creation: the signatures are the whole layout.
      diag.error(pipeline.where, "pipeline '" + pipeline.name +
                                     "' uses resource signatures and also lists ResourceLayout " +
                                     (pipeline.variables.empty() ? "immutable samplers" : "variables") +
                                     ", which Diligent refuses: with signatures, the signatures are the "
                                     "layout (put the variables and samplers there)");
      return false;
    }
    return layout_from_signatures(pipeline, stages, notation, builder, out, diag) &&
           push_inline_constants(pipeline, pushed, stages, out, diag);
  }
  return implicit_layout(pipeline, stages, builder, notation.sources, options, pushed.name, out, diag) &&
         push_inline_constants(pipeline, pushed, stages, out, diag);
}

}  // namespace statepack::packager
