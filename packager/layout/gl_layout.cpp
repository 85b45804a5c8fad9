#include "gl_layout.hpp"

#include <vulkan/vulkan_core.h>

#include <algorithm>
#include <array>
#include <map>
#include <optional>
#include <string>
#include <tuple>

#include "block_views.hpp"
#include "interface_check.hpp"
#include "shaders/gl_translate.hpp"

namespace statepack::packager {
namespace {

struct Merged {
  format::GlNamespace kind;
  uint32_t count = 1;
  uint32_t stages = 0;
  std::tuple<uint32_t, uint32_t> declared;  // (set, binding) where first seen: the numbering order
  std::string block_layout;                 // a block's members as the first stage declares them
  std::string first_shader;                 // "shader 'X'" that declared it first, for messages
  bool views_differ = false;                // stages declare other members: merged (block_views.hpp)
};

const char* gl_limit_name(format::GlNamespace kind) {
  switch (kind) {
    case format::GlNamespace::uniform_buffer:
      return "GL_MAX_UNIFORM_BUFFER_BINDINGS";
    case format::GlNamespace::storage_buffer:
      return "GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS";
    case format::GlNamespace::texture:
      return "GL_MAX_COMBINED_TEXTURE_IMAGE_UNITS";
    case format::GlNamespace::image:
      return "GL_MAX_IMAGE_UNITS";
  }
  return "";
}

// The blocks whose stages declare different members: merged into one definition in every stage's
// patched module (the last change made to them), or an error naming the members that conflict.
bool merge_views(const PipelineDesc& p, const std::vector<StageInput>& stages,
                 const std::map<std::string, Merged>& by_name, GlLayout& out, Diagnostics& diag) {
  for (const auto& [name, merged] : by_name) {
    if (!merged.views_differ) continue;
    std::vector<BlockView> views;
    for (size_t s = 0; s < stages.size(); ++s)
      for (const ReflectedBinding& b : stages[s].reflection->bindings)
        if (b.name == name) views.push_back({&out.patched_spirv[s], b.variable, stage_text(*stages[s].desc)});
    if (std::string problem = merge_block_views(views); !problem.empty()) {
      const std::string block =
          name == kGlPushConstantsName ? std::string("the push constants") : "the block '" + name + "'";
      diag.error(p.where, "pipeline '" + p.name + "' (OpenGL): its stages declare " + block +
                              " differently, and OpenGL links one definition per block: " + problem +
                              " (views that agree wherever they overlap are merged)");
      return false;
    }
  }
  return true;
}

}  // namespace

uint32_t gl_guaranteed_units(format::GlNamespace kind) {
  switch (kind) {
    case format::GlNamespace::uniform_buffer:
      return 84;
    case format::GlNamespace::storage_buffer:
      return 8;
    case format::GlNamespace::texture:
      return 80;
    case format::GlNamespace::image:
      return 8;
  }
  return 0;
}

std::string gl_units_exceeded(const std::vector<ReflectedBinding>& bindings) {
  std::array<uint64_t, format::kGlNamespaceCount> needed{};
  std::array<const ReflectedBinding*, format::kGlNamespaceCount> largest{};
  for (const ReflectedBinding& b : bindings) {
    // A separate image becomes a texture with its sampler; a separate sampler takes no unit of its own.
    const auto kind = b.descriptor_type == VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE
                          ? format::GlNamespace::texture
                          : format::gl_namespace_of(b.descriptor_type);
    if (!kind) continue;
    const size_t k = size_t(*kind);
    needed[k] += std::max(b.count, 1u);
    if (!largest[k] || b.count > largest[k]->count) largest[k] = &b;
  }
  for (size_t k = 0; k < needed.size(); ++k) {
    const auto kind = format::GlNamespace(k);
    if (needed[k] <= gl_guaranteed_units(kind)) continue;
    const ReflectedBinding& big = *largest[k];
    return "needs " + std::to_string(needed[k]) + " " + format::gl_namespace_name(uint32_t(k)) +
           " binding points" +
           (big.count > 1 ? " ('" + big.name + "' is an array of " + std::to_string(big.count) + ")" : "") +
           ", but OpenGL 4.5 guarantees " + std::to_string(gl_guaranteed_units(kind)) + " (" +
           gl_limit_name(kind) +
           "): Vulkan's descriptor arrays have no such bound; split the array, or leave this pipeline out of "
           "the OpenGL backend";
  }
  return "";
}

bool build_gl_layout(const PipelineDesc& p, const std::vector<StageInput>& stages, GlLayout& out,
                     Diagnostics& diag) {
  const std::string who = "pipeline '" + p.name + "' (OpenGL)";
  bool ok = true;
  std::map<std::string, Merged> by_name;
  for (const StageInput& stage : stages) {
    const std::string shader = "shader '" + stage.desc->name + "'";
    if (stage.reflection->push_constant_size > 0) {
      diag.error(stage.desc->where, who + ": " + shader +
                                        " has push constants when VULKAN is not defined, which OpenGL does "
                                        "not have; declare a uniform block there, or drop the #ifdef VULKAN "
                                        "branches to let statepack translate the Vulkan code");
      ok = false;
    }
    for (const ReflectedBinding& b : stage.reflection->bindings) {
      const auto kind = format::gl_namespace_of(b.descriptor_type);
      if (!kind) {
        diag.error(stage.desc->where,
                   who + ": " + shader + " declares '" + b.name + "' as a " +
                       format::descriptor_type_name(b.descriptor_type) +
                       ", which OpenGL does not have; use a combined sampler (sampler2D and the like) or a "
                       "storage image for OpenGL");
        ok = false;
        continue;
      }
      const uint32_t count = std::max(b.count, 1u);  // a runtime array takes one binding
      if (count > 1024) {  // the archive's limit (validate_gl_pipeline); devices allow far fewer units
        diag.error(stage.desc->where, who + ": " + shader + " declares '" + b.name + "' as an array of " +
                                          std::to_string(count) + "; OpenGL bindings hold at most 1024");
        ok = false;
        continue;
      }
      auto [it, inserted] = by_name.try_emplace(
          b.name, Merged{*kind, count, b.stage, {b.set, b.binding}, b.block_layout, shader});
      if (!inserted && it->second.block_layout != b.block_layout) {
        // Vulkan lets each stage declare its own view of a buffer (push constants especially: each stage
        // its range); OpenGL links one definition per block: the views are merged once patched.
        it->second.views_differ = true;
      }
      if (!inserted && (it->second.kind != *kind || it->second.count != count)) {
        diag.error(stage.desc->where, who + ": " + shader + " declares '" + b.name +
                                          "' differently from another stage (kind or array size)");
        ok = false;
      }
      it->second.stages |= b.stage;
    }
  }
  if (!ok) return false;
  std::vector<ReflectedBinding> merged;  // the program's, against OpenGL's guaranteed binding points
  for (const auto& [name, m] : by_name) {
    static constexpr uint32_t kTypeOf[] = {
        VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
        VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE};
    ReflectedBinding b;
    b.name = name, b.descriptor_type = kTypeOf[size_t(m.kind)], b.count = m.count;
    merged.push_back(b);
  }
  if (std::string exceeded = gl_units_exceeded(merged); !exceeded.empty()) {
    diag.error(p.where, who + ": its shaders together " + exceeded);
    return false;
  }

  // Numbers per kind, in declaration order.
  std::vector<std::pair<const std::string*, const Merged*>> ordered;
  for (const auto& [name, m] : by_name) ordered.emplace_back(&name, &m);
  std::sort(ordered.begin(), ordered.end(), [](const auto& a, const auto& b) {
    return std::tie(a.second->declared, *a.first) < std::tie(b.second->declared, *b.first);
  });
  std::array<uint32_t, format::kGlNamespaceCount> next{};
  std::map<std::string, uint32_t> number;
  for (const auto& [name, m] : ordered) {
    uint32_t& n = next[size_t(m->kind)];
    number[*name] = n;
    out.bindings.push_back({*name, uint32_t(m->kind), n, m->count, m->stages});
    n += m->count;
  }
  std::sort(out.bindings.begin(), out.bindings.end(),
            [](const format::GlBinding& a, const format::GlBinding& b) {
              return std::tie(a.kind, a.binding) < std::tie(b.kind, b.binding);
            });

  for (const StageInput& stage : stages) {
    std::vector<uint32_t> spirv = *stage.spirv;
    for (const ReflectedBinding& b : stage.reflection->bindings) {
      if (b.binding_word == 0 || b.binding_word >= spirv.size()) {
        diag.error(stage.desc->where, who + ": shader '" + stage.desc->name + "': '" + b.name +
                                          "' has no Binding decoration to patch");
        return false;
      }
      spirv[b.binding_word] = number.at(b.name);
      if (b.set_word != 0 && b.set_word < spirv.size()) spirv[b.set_word] = 0;
    }
    out.patched_spirv.push_back(std::move(spirv));
  }
  return merge_views(p, stages, by_name, out, diag);
}

}  // namespace statepack::packager
