#include "gl_layout.hpp"

#include <algorithm>
#include <array>
#include <map>
#include <optional>
#include <string>
#include <tuple>

#include "shaders/gl_translate.hpp"

namespace statepack::packager {
namespace {

struct Merged {
  format::GlNamespace kind;
  uint32_t count = 1;
  uint32_t stages = 0;
  std::tuple<uint32_t, uint32_t> declared;  // (set, binding) where first seen: the numbering order
  std::string block_layout;                 // a block's members: every stage must declare the same
  std::string first_shader;                 // "shader 'X'" that declared it first, for messages
};

}  // namespace

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
        // its range); OpenGL links one definition per block and refuses the program otherwise.
        const std::string block = b.name == kGlPushConstantsName ? std::string("the push-constant block")
                                                                 : "the block '" + b.name + "'";
        diag.error(stage.desc->where,
                   who + ": " + shader + " declares " + block + " with other members or offsets than " +
                       it->second.first_shader +
                       "; OpenGL links one definition per block, so declare it alike in every stage (all "
                       "members, at the same offsets; a shared #include)");
        ok = false;
      } else if (!inserted && (it->second.kind != *kind || it->second.count != count)) {
        diag.error(stage.desc->where, who + ": " + shader + " declares '" + b.name +
                                          "' differently from another stage (kind or array size)");
        ok = false;
      }
      it->second.stages |= b.stage;
    }
  }
  if (!ok) return false;

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
  return true;
}

}  // namespace statepack::packager
