#include "inline_constants.hpp"

#include <vulkan/vulkan_core.h>

#include <algorithm>
#include <map>

#include "shaders/push_constant_conversion.hpp"

namespace statepack::packager {

InlineConstants pushed_inline_constants(const PipelineDesc& p, const Notation& notation) {
  InlineConstants out;
  if (!p.signatures.empty()) {
    std::map<uint32_t, const SignatureDesc*> by_set;
    for (const std::string& name : p.signatures)
      if (auto it = notation.signature_index.find(name); it != notation.signature_index.end())
        by_set.emplace(notation.signatures[it->second].binding_index, &notation.signatures[it->second]);
    for (const auto& [set, sig] : by_set) {
      std::vector<const SignatureResource*> flagged;
      for (const SignatureResource& r : sig->resources)
        if (r.inline_constants) flagged.push_back(&r);
      std::stable_sort(flagged.begin(), flagged.end(),
                       [](const auto* a, const auto* b) { return a->var_type < b->var_type; });
      for (const SignatureResource* r : flagged) {
        if (!out.name.empty()) {
          out.others.push_back(r->name);
          continue;
        }
        out.name = r->name;
        out.values = r->inline_constants;
        out.stages = r->stages;
        out.where = sig->where;
      }
    }
    return out;
  }
  for (const ResourceVariable& v : p.variables) {
    if (!v.inline_constants) continue;
    if (!out.name.empty()) {
      out.others.push_back(v.name);
      continue;
    }
    out.name = v.name;
    out.stages = v.stages;
    out.where = p.where;
  }
  return out;
}

bool push_inline_constants(const PipelineDesc& p, const InlineConstants& pushed,
                           const std::vector<StageInput>& stages, PipelineLayout& out, Diagnostics& diag) {
  if (pushed.name.empty()) return true;
  const std::string who = "pipeline '" + p.name + "'";
  for (const std::string& other : pushed.others)
    for (const StageInput& stage : stages)
      if (std::any_of(stage.reflection->bindings.begin(), stage.reflection->bindings.end(),
                      [&](const ReflectedBinding& b) { return b.name == other; })) {
        diag.warning(p.where,
                     who + ": inline constants '" + other +
                         "' stay a uniform buffer the application "
                         "binds: '" +
                         pushed.name +
                         "' has the pipeline's push constants (Vulkan has one push-constant block per "
                         "stage; Diligent fills such a buffer itself)");
        break;
      }
  uint32_t block_bytes = 0, used_by = 0;
  for (size_t s = 0; s < stages.size(); ++s) {
    const StageInput& stage = stages[s];
    const Reflection& r = *stage.reflection;
    const std::string where = who + ", shader '" + stage.desc->name + "'";
    if (r.push_constant_size > 0) {
      if (r.push_constant_name != pushed.name) {
        diag.error(stage.desc->where, where + ": declares push constants '" + r.push_constant_name +
                                          "', but the pipeline pushes inline constants '" + pushed.name +
                                          "' (a stage has one push-constant block)");
        return false;
      }
      block_bytes = std::max(block_bytes, r.push_constant_size);  // declared as push constants already
      used_by |= stage.desc->stage;
      continue;
    }
    auto block = std::find_if(r.bindings.begin(), r.bindings.end(),
                              [&](const ReflectedBinding& b) { return b.name == pushed.name; });
    if (block == r.bindings.end()) continue;
    if (block->descriptor_type != VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER || block->count != 1) {
      diag.error(stage.desc->where,
                 where + ": inline constants '" + pushed.name +
                     "' must be a uniform buffer (cbuffer, ConstantBuffer<T>, uniform block) "
                     "that is not an array");
      return false;
    }
    if (std::string problem = uniform_block_to_push_constants(out.patched_spirv[s], block->variable);
        !problem.empty()) {
      diag.error(stage.desc->where,
                 where + ": cannot make uniform buffer '" + pushed.name + "' its push constants: " + problem);
      return false;
    }
    block_bytes = std::max(block_bytes, block->block_size);
    used_by |= stage.desc->stage;
  }
  if (used_by == 0) return true;  // no stage uses it: nothing to push
  uint32_t bytes = pushed.values * 4;
  if (pushed.values == 0) {  // a ResourceLayout variable: the block decides
    bytes = (block_bytes + 3) / 4 * 4;
    if (bytes > kGuaranteedInlineConstants * 4) {
      diag.error(pushed.where, who + ": inline constants '" + pushed.name + "' are " + std::to_string(bytes) +
                                   " bytes, more than the 128 bytes of push constants Vulkan guarantees "
                                   "(maxPushConstantsSize)");
      return false;
    }
  } else if (block_bytes > bytes) {
    diag.error(pushed.where, who + ": the shaders' block '" + pushed.name + "' is " +
                                 std::to_string(block_bytes) + " bytes, but its ArraySize gives " +
                                 std::to_string(pushed.values) + " values (" + std::to_string(bytes) +
                                 " bytes): the range pushed must hold the whole block");
    return false;
  }
  out.push_constant_size = std::max(out.push_constant_size, bytes);
  uint32_t pipeline_stages = 0;
  for (const StageInput& stage : stages) pipeline_stages |= stage.desc->stage;
  out.push_constant_stages |= (pushed.stages & pipeline_stages) | used_by;
  return true;
}

}  // namespace statepack::packager
