#include "interface_check.hpp"

#include <vulkan/vulkan_core.h>

#include <algorithm>
#include <map>
#include <set>
#include <string>

#include "format/spirv_walk.hpp"
#include "format_support.hpp"

namespace statepack::packager {
namespace {

using Base = InterfaceVariable::Base;

// The notation's slot names the stages (pVS, pPS, ...), so messages use Diligent's stage words.
const char* stage_noun(uint32_t stage) {
  switch (stage) {
    case VK_SHADER_STAGE_VERTEX_BIT:
      return "vertex shader";
    case VK_SHADER_STAGE_TESSELLATION_CONTROL_BIT:
      return "hull shader";
    case VK_SHADER_STAGE_TESSELLATION_EVALUATION_BIT:
      return "domain shader";
    case VK_SHADER_STAGE_GEOMETRY_BIT:
      return "geometry shader";
    case VK_SHADER_STAGE_FRAGMENT_BIT:
      return "pixel shader";
    default:
      return "shader";
  }
}

std::string shader_text(const StageInput& s) {
  return stage_text(*s.desc);
}

// The variable's type as its source language spells it: "vec3", "flat ivec4", "float4", "uint2[3]".
std::string type_text(const InterfaceVariable& v, SourceLanguage language) {
  std::string t;
  const bool hlsl = language == SourceLanguage::hlsl;
  if (v.base == Base::other) {
    t = "struct";
  } else if (hlsl) {
    t = v.base == Base::floating     ? (v.bit_width == 64   ? "double"
                                        : v.bit_width == 16 ? "half"
                                                            : "float")
        : v.base == Base::signed_int ? (v.bit_width == 64 ? "int64_t" : "int")
                                     : (v.bit_width == 64 ? "uint64_t" : "uint");
    if (v.columns > 1)
      t += std::to_string(v.vector_size) + "x" + std::to_string(v.columns);
    else if (v.vector_size > 1)
      t += std::to_string(v.vector_size);
  } else {
    const char* prefix = v.base == Base::floating     ? (v.bit_width == 64   ? "d"
                                                         : v.bit_width == 16 ? "f16"
                                                                             : "")
                         : v.base == Base::signed_int ? (v.bit_width == 64 ? "i64" : "i")
                                                      : (v.bit_width == 64 ? "u64" : "u");
    if (v.columns > 1) {
      t = std::string(v.bit_width == 64 ? "d" : "") + "mat" + std::to_string(v.columns);
      if (v.columns != v.vector_size) t += "x" + std::to_string(v.vector_size);
    } else if (v.vector_size > 1) {
      t = std::string(prefix) + "vec" + std::to_string(v.vector_size);
    } else {
      t = v.base == Base::floating     ? (v.bit_width == 64   ? "double"
                                          : v.bit_width == 16 ? "float16_t"
                                                              : "float")
          : v.base == Base::signed_int ? (v.bit_width == 64 ? "int64_t" : "int")
                                       : (v.bit_width == 64 ? "uint64_t" : "uint");
    }
  }
  if (v.array_size > 1) t += "[" + std::to_string(v.array_size) + "]";
  return (v.flat ? (hlsl ? "nointerpolation " : "flat ") : "") + t;
}

std::string kind_text(const InterfaceVariable& v) {
  std::string width = v.bit_width == 32 ? "" : std::to_string(v.bit_width) + "-bit ";
  switch (v.base) {
    case Base::floating:
      return width + "float";
    case Base::signed_int:
      return width + "signed integer";
    case Base::unsigned_int:
      return width + "unsigned integer";
    case Base::other:
      break;
  }
  return "struct";
}

// "'vec3 normal'"; glslang names what an HLSL entry point returns "@entryPointOutput": shown as
// "'float3 vs_main().normal'".
std::string describe(const InterfaceVariable& v, const StageInput& s) {
  std::string name = v.name;
  if (name.starts_with("@entryPointOutput")) name.replace(0, 17, std::string(s.entry_point) + "()");
  return "'" + type_text(v, s.desc->language) + " " + name + "'";
}

// One location's worth of a variable: components [first, end) of `location`, in 32-bit words.
struct Slot {
  uint32_t location, first, end;
  const InterfaceVariable* variable;
};

std::vector<Slot> slots_of(const InterfaceVariable& v) {
  std::vector<Slot> out;
  const uint32_t words = v.vector_size * (v.bit_width == 64 ? 2 : 1);
  const uint32_t per_column = v.locations_per_column();
  // Arrays of thousands of locations are not valid Vulkan (maxVertexOutputComponents is ~128 words),
  // so a hostile array size is cut short instead of listed.
  const uint32_t count = std::min<uint32_t>(v.array_size * v.columns, 64);
  for (uint32_t i = 0; i < count; ++i) {
    const uint32_t location = v.location + i * per_column;
    if (per_column == 1) {
      out.push_back({location, v.component, v.component + words, &v});
    } else {
      out.push_back({location, v.component, 4, &v});
      out.push_back({location + 1, 0, words - (4 - v.component), &v});
    }
  }
  return out;
}

std::string location_list(const std::set<uint32_t>& locations) {
  if (locations.empty()) return "none";
  std::string out;
  for (uint32_t l : locations) out += (out.empty() ? "" : ", ") + std::to_string(l);
  return out;
}

bool same_kind(const InterfaceVariable& a, const InterfaceVariable& b) {
  return a.base == b.base && a.bit_width == b.bit_width;
}

// What `producer` writes, `consumer` reads: same component type, at least as many components.
bool check_stage_pair(const PipelineDesc& p, const StageInput& producer, const StageInput& consumer,
                      Diagnostics& diag) {
  std::multimap<uint32_t, Slot> written;
  std::set<uint32_t> written_locations;
  for (const InterfaceVariable& v : producer.reflection->outputs) {
    if (v.base == Base::other) return true;  // a struct member we do not model: no claims either way
    for (const Slot& s : slots_of(v)) {
      written.emplace(s.location, s);
      written_locations.insert(s.location);
    }
  }
  bool ok = true;
  for (const InterfaceVariable& v : consumer.reflection->inputs) {
    if (v.base == Base::other) continue;
    std::string problem;
    for (const Slot& in : slots_of(v)) {
      const Slot* covering = nullptr;
      const Slot* clashing = nullptr;
      const Slot* partial = nullptr;
      auto [first, last] = written.equal_range(in.location);
      for (auto it = first; it != last; ++it) {
        const Slot& out = it->second;
        if (out.end <= in.first || out.first >= in.end) continue;  // other components of the location
        if (!same_kind(*out.variable, v))
          clashing = &out;
        else if (out.first <= in.first && out.end >= in.end)
          covering = &out;
        else
          partial = &out;
      }
      if (clashing) {
        problem = "reads " + describe(v, consumer) + " at location " + std::to_string(in.location) + " as " +
                  kind_text(v) + ", but " + shader_text(producer) + " writes " +
                  describe(*clashing->variable, producer) + " there as " + kind_text(*clashing->variable);
      } else if (!covering && partial) {
        problem = "reads " + std::to_string(in.end - in.first) + " component(s) of location " +
                  std::to_string(in.location) + " (" + describe(v, consumer) + "), but " +
                  shader_text(producer) + " writes only " + std::to_string(partial->end - partial->first) +
                  " (" + describe(*partial->variable, producer) + ")";
      } else if (!covering && written_locations.count(in.location)) {
        problem = "reads " + describe(v, consumer) + " at component " + std::to_string(in.first) +
                  " of location " + std::to_string(in.location) + ", which " + shader_text(producer) +
                  " does not write (it writes other components of that location)";
      } else if (!covering) {
        problem = "reads " + describe(v, consumer) + " at location " + std::to_string(in.location) +
                  ", which " + shader_text(producer) + " does not write (it writes location(s) " +
                  location_list(written_locations) + ")";
      }
      if (!problem.empty()) break;  // one message per variable, not per location
    }
    if (!problem.empty()) {
      diag.error(consumer.desc->where, "pipeline '" + p.name + "': " + shader_text(consumer) + " " + problem);
      ok = false;
    } else if (consumer.desc->stage == VK_SHADER_STAGE_FRAGMENT_BIT && !v.flat &&
               (v.base != Base::floating || v.bit_width == 64)) {
      diag.error(consumer.desc->where,
                 "pipeline '" + p.name + "': " + shader_text(consumer) + " reads " + describe(v, consumer) +
                     " without 'flat' (nointerpolation in HLSL): Vulkan requires integer "
                     "and 64-bit pixel-shader inputs to be flat");
      ok = false;
    }
  }
  // What the next stage never reads is wasted work, and the validation layer says so (a performance
  // warning): warn here, once per variable.
  std::multimap<uint32_t, Slot> read;
  for (const InterfaceVariable& v : consumer.reflection->inputs)
    for (const Slot& s : slots_of(v)) read.emplace(s.location, s);
  for (const InterfaceVariable& v : producer.reflection->outputs) {
    for (const Slot& out : slots_of(v)) {
      auto [first, last] = read.equal_range(out.location);
      if (std::any_of(first, last,
                      [&](const auto& in) { return in.second.first < out.end && in.second.end > out.first; }))
        continue;
      diag.warning(consumer.desc->where, "pipeline '" + p.name + "': " + shader_text(producer) + " writes " +
                                             describe(v, producer) + " at location " +
                                             std::to_string(out.location) + ", which " +
                                             shader_text(consumer) +
                                             " does not read (the validation layer reports this as a "
                                             "performance warning)");
      break;
    }
  }
  return ok;
}

NumericClass class_of(const InterfaceVariable& v) {
  switch (v.base) {
    case Base::floating:
      return NumericClass::floating;
    case Base::signed_int:
      return NumericClass::signed_int;
    case Base::unsigned_int:
      return NumericClass::unsigned_int;
    case Base::other:
      break;
  }
  return NumericClass::none;
}

// Every vertex-shader input comes from an input-layout element whose format the shader can read.
bool check_input_layout(const PipelineDesc& p, const format::GraphicsState& g, const StageInput& vs,
                        const SourceTexts& sources, Diagnostics& diag) {
  const std::string layout = p.where.pointer + "/GraphicsPipeline/InputLayout";
  auto element = [&](size_t i) {
    return sources.at(p.where, layout + "/LayoutElements/" + std::to_string(i));
  };
  std::map<uint32_t, size_t> by_location;
  std::set<uint32_t> given;
  for (size_t i = 0; i < g.vertex_attributes.size(); ++i) {
    by_location.emplace(g.vertex_attributes[i].location, i);
    given.insert(g.vertex_attributes[i].location);
  }
  std::set<uint32_t> read;
  bool ok = true;
  for (const InterfaceVariable& v : vs.reflection->inputs) {
    if (v.base == Base::other) continue;
    const uint32_t locations = std::min<uint32_t>(v.array_size * v.columns, 64);
    for (uint32_t l = 0; l < locations; ++l) read.insert(v.location + l);
    for (uint32_t l = 0; l < locations; ++l) {
      auto it = by_location.find(v.location + l);
      if (it == by_location.end()) {
        diag.error(sources.at(p.where, layout),
                   "pipeline '" + p.name + "': " + shader_text(vs) + " reads " + describe(v, vs) +
                       " at location " + std::to_string(v.location + l) +
                       ", but InputLayout has no element with InputIndex " + std::to_string(v.location + l) +
                       " (it has " + location_list(given) + ")");
        ok = false;
        break;
      }
      const uint32_t format = g.vertex_attributes[it->second].format;
      const NumericClass have = numeric_class(format), want = class_of(v);
      if (have != want || v.bit_width == 64) {
        diag.error(element(it->second),
                   "pipeline '" + p.name + "': InputLayout element " + std::to_string(it->second) +
                       " (InputIndex " + std::to_string(v.location + l) + ") is " + format_name(format) +
                       ", read as " + numeric_class_name(have) + ", but " + shader_text(vs) + " declares " +
                       describe(v, vs) + " (" + kind_text(v) +
                       "): ValueType and IsNormalized must give the shader's component type (float: FLOAT*, "
                       "or normalized integers; int: INT* with IsNormalized false; uint: UINT* with "
                       "IsNormalized false)");
        ok = false;
        break;
      }
    }
  }
  for (size_t i = 0; i < g.vertex_attributes.size(); ++i) {
    const format::VertexAttribute& a = g.vertex_attributes[i];
    if (!read.count(a.location))
      diag.warning(element(i), "pipeline '" + p.name + "': InputLayout element " + std::to_string(i) +
                                   " (InputIndex " + std::to_string(a.location) +
                                   ") is read by no input of " + shader_text(vs) + " (it reads location(s) " +
                                   location_list(read) + ")");
    if (!guaranteed_vertex_buffer(a.format))
      diag.warning(element(i),
                   "pipeline '" + p.name + "': InputLayout element " + std::to_string(i) + " is " +
                       format_name(a.format) +
                       ", which Vulkan does not require devices to support as a vertex format "
                       "(3-component 8- and 16-bit formats are often missing): prefer 4 components");
  }
  return ok;
}

// Every fragment output lands on a render target whose format holds its kind of value; integer targets
// are not blended.
bool check_render_targets(const PipelineDesc& p, const format::GraphicsState& g, const StageInput* ps,
                          const SourceTexts& sources, Diagnostics& diag) {
  const std::string gp = p.where.pointer + "/GraphicsPipeline";
  const bool from_render_pass = !p.render_pass.empty();
  auto target_where = [&](uint32_t i) {
    return sources.at(p.where,
                      from_render_pass ? gp + "/pRenderPass" : gp + "/RTVFormats/" + std::to_string(i));
  };
  bool ok = true;
  std::set<uint32_t> run_time_targets;  // written, with no target in the notation: the callback's to set
  if (ps) {
    for (const InterfaceVariable& v : ps->reflection->outputs) {
      if (v.base == Base::other) continue;
      for (uint32_t e = 0; e < std::min<uint32_t>(v.array_size, 64); ++e) {
        const uint32_t location = v.location + e;
        if (location >= format::kMaxColorTargets) {  // no patch can give a pipeline a ninth target
          diag.error(sources.at(p.where, gp),
                     "pipeline '" + p.name + "': " + shader_text(*ps) + " writes " + describe(v, *ps) +
                         " to location " + std::to_string(location) + ", but a pipeline has at most " +
                         std::to_string(format::kMaxColorTargets) + " render targets");
          ok = false;
          break;
        }
        if (location >= g.color_count && !from_render_pass) {
          // Diligent's workflow: the application sets the count and formats in its modify callback
          // (Tutorial25's notation gives none), so the truth is known at unpack, which checks it.
          run_time_targets.insert(location);
          continue;
        }
        if (location >= g.color_count) {  // valid Vulkan (the write is discarded), as Diligent accepts it
          diag.warning(sources.at(p.where, gp + "/pRenderPass"),
                       "pipeline '" + p.name + "': " + shader_text(*ps) + " writes " + describe(v, *ps) +
                           " to location " + std::to_string(location) + ", but subpass " +
                           std::to_string(p.subpass) + " of render pass '" + p.render_pass + "' has " +
                           std::to_string(g.color_count) +
                           " color attachment(s): what it writes there is discarded");
          break;
        }
        const uint32_t format = g.color_formats[location];
        const NumericClass have = numeric_class(format), want = class_of(v);
        if (have != NumericClass::none && have != want) {  // none: UNKNOWN, patched at run time
          const std::string what = "pipeline '" + p.name + "': render target " + std::to_string(location) +
                                   " is " + format_name(format) + " (" + numeric_class_name(have) +
                                   "), but " + shader_text(*ps) + " writes " + describe(v, *ps) + " (" +
                                   kind_text(v) + ") to it: the values written would be undefined";
          if (from_render_pass) {  // a render pass's formats are its own: no patch changes them
            diag.error(target_where(location), what);
            ok = false;
          } else {  // the modify callback can set the format; unpack checks what it leaves
            diag.warning(target_where(location),
                         what + "; give a " + kind_text(v) +
                             " format in RTVFormats, or set one in the modify callback "
                             "(PatchableState::color_formats), or unpacking fails");
          }
          break;
        }
      }
    }
  }
  if (!run_time_targets.empty()) {
    std::string list;
    for (uint32_t l : run_time_targets) list += (list.empty() ? "" : ", ") + std::to_string(l);
    diag.note(sources.at(p.where, gp),
              "pipeline '" + p.name + "': " + shader_text(*ps) + " writes render target(s) " + list +
                  ", which the notation leaves to run time (" + std::to_string(g.color_count) +
                  " in NumRenderTargets/RTVFormats): give them in the notation (NumRenderTargets and "
                  "RTVFormats), or set them in the modify callback (PatchableState::color_count and "
                  "color_formats), or unpacking fails");
  }
  for (uint32_t i = 0; i < g.color_count && i < format::kMaxColorTargets; ++i) {
    const uint32_t format = g.color_formats[i];
    if (format == VK_FORMAT_UNDEFINED) continue;
    const std::string blend = gp + "/BlendDesc/RenderTargets/" + std::to_string(i) + "/BlendEnable";
    const bool integer = numeric_class(format) != NumericClass::floating;
    if (g.blend[i].enable && integer)  // blending and formats are patchable: unpack checks what is left
      diag.warning(sources.at(p.where, blend),
                   "pipeline '" + p.name + "': blending is enabled for render target " + std::to_string(i) +
                       ", whose format " + format_name(format) +
                       " is an integer format: Vulkan cannot blend integer formats, so the modify callback "
                       "must turn its blending off (PatchableState::blend) or set a float format, or "
                       "unpacking fails (set BlendEnable to false for it; with IndependentBlendEnable false, "
                       "render target 0's blending applies to all)");
    if (from_render_pass) continue;  // the render pass's attachments are its own object
    if (!guaranteed_color_attachment(format))
      diag.warning(target_where(i), "pipeline '" + p.name + "': render target " + std::to_string(i) + " is " +
                                        format_name(format) +
                                        ", which Vulkan does not require devices to support as a color "
                                        "attachment: some devices will refuse this pipeline");
    else if (g.blend[i].enable && !integer && !guaranteed_color_blend(format))
      diag.warning(sources.at(p.where, blend),
                   "pipeline '" + p.name + "': blending is enabled for render target " + std::to_string(i) +
                       ", but Vulkan does not require devices to blend " + format_name(format) +
                       ": some devices will refuse this pipeline");
  }
  return ok;
}

}  // namespace

std::string stage_text(const ShaderDesc& shader) {
  return std::string(stage_noun(shader.stage)) + " '" + shader.name + "'";
}

bool check_graphics_interfaces(const PipelineDesc& p, const format::GraphicsState& g,
                               const std::vector<StageInput>& stages, const SourceTexts& sources,
                               Diagnostics& diag) {
  // Pipeline order of the stages present (the notation lists slots in any order).
  static constexpr uint32_t kOrder[] = {VK_SHADER_STAGE_VERTEX_BIT, VK_SHADER_STAGE_TESSELLATION_CONTROL_BIT,
                                        VK_SHADER_STAGE_TESSELLATION_EVALUATION_BIT,
                                        VK_SHADER_STAGE_GEOMETRY_BIT, VK_SHADER_STAGE_FRAGMENT_BIT};
  std::vector<const StageInput*> ordered;
  for (uint32_t stage : kOrder)
    for (const StageInput& s : stages)
      if (s.desc->stage == stage) ordered.push_back(&s);
  bool ok = true;
  for (size_t i = 0; i + 1 < ordered.size(); ++i)
    ok &= check_stage_pair(p, *ordered[i], *ordered[i + 1], diag);
  if (!ordered.empty() && ordered.front()->desc->stage == VK_SHADER_STAGE_VERTEX_BIT)
    ok &= check_input_layout(p, g, *ordered.front(), sources, diag);
  const StageInput* ps = !ordered.empty() && ordered.back()->desc->stage == VK_SHADER_STAGE_FRAGMENT_BIT
                             ? ordered.back()
                             : nullptr;
  ok &= check_render_targets(p, g, ps, sources, diag);
  // Input attachments are read from the subpass's attachments: without a render pass (dynamic
  // rendering) there are none (VUID-VkGraphicsPipelineCreateInfo-renderPass-06061), and no run-time patch
  // gives a pipeline a render pass.
  if (p.render_pass.empty())
    for (const StageInput& s : stages)
      for (const ReflectedBinding& b : s.reflection->bindings)
        if (b.descriptor_type == VK_DESCRIPTOR_TYPE_INPUT_ATTACHMENT) {
          diag.error(s.desc->where, "pipeline '" + p.name + "': " + shader_text(s) +
                                        " reads input attachment '" + b.name + "' (set " +
                                        std::to_string(b.set) + ", binding " + std::to_string(b.binding) +
                                        "), which needs a render pass: give the pipeline a pRenderPass whose "
                                        "subpass lists its input attachments (dynamic rendering has none)");
          ok = false;
        }
  // Points take their size from the last stage before rasterization; when that is the vertex shader, it
  // must write PointSize (VUID-VkGraphicsPipelineCreateInfo-topology-08773). The dearchiver's own SPIR-V
  // walker decides "writes", so pack and unpack cannot disagree.
  if (g.topology == VK_PRIMITIVE_TOPOLOGY_POINT_LIST && !ordered.empty() &&
      ordered.front()->desc->stage == VK_SHADER_STAGE_VERTEX_BIT &&
      std::none_of(ordered.begin(), ordered.end(), [](const StageInput* s) {
        return s->desc->stage == VK_SHADER_STAGE_GEOMETRY_BIT ||
               s->desc->stage == VK_SHADER_STAGE_TESSELLATION_EVALUATION_BIT;
      })) {
    std::optional<spirv::Module> walked;
    const spirv::Module* module = ordered.front()->module;
    if (!module)
      if (auto w = spirv::walk(*ordered.front()->spirv)) module = &walked.emplace(std::move(*w));
    if (module && !module->writes_point_size) {
      diag.error(sources.at(p.where, p.where.pointer + "/GraphicsPipeline/PrimitiveTopology"),
                 "pipeline '" + p.name + "' draws points (POINT_LIST), but " + shader_text(*ordered.front()) +
                     " does not write PointSize (gl_PointSize; in HLSL an output with "
                     "[[vk::builtin(\"PointSize\")]]): Vulkan needs each point's size");
      ok = false;
    }
  }
  return ok;
}

void warn_compute_work_group(const PipelineDesc& p, const StageInput& stage,
                             const std::vector<format::SpecConstant>& constants, WalkedModules& walked,
                             Diagnostics& diag) {
  const spirv::Module* module = stage.module;
  if (!module) {
    auto [it, fresh] = walked.try_emplace(stage.spirv);
    if (fresh)
      if (auto m = spirv::walk(*stage.spirv)) it->second = std::move(*m);
    if (!it->second) return;
    module = &*it->second;
  }
  const spirv::EntryPoint* entry =
      module->find(*spirv::execution_model_of_stage(VK_SHADER_STAGE_COMPUTE_BIT), stage.entry_point);
  if (!entry || !entry->workgroup_size) return;
  // The pipeline's 4-byte compute constant with that SpecId, as the dearchiver applies it.
  auto specialized = [&](uint32_t spec_id) -> std::optional<uint32_t> {
    for (const auto& k : constants)
      if (k.constant_id == spec_id && k.stage == VK_SHADER_STAGE_COMPUTE_BIT && k.size == 4)
        return uint32_t(k.value);
    return std::nullopt;
  };
  const spirv::WorkgroupSize size = spirv::specialized_workgroup_size(*entry->workgroup_size, specialized);
  static constexpr uint64_t kGuaranteedSize[3] = {128, 128, 64}, kGuaranteedInvocations = 128;
  const std::string text = spirv::workgroup_size_text(size);
  // stage.desc is the pipeline's own shader slot (its name and place in the notation).
  const std::string who = "pipeline '" + p.name + "': shader '" + stage.desc->name + "'";
  if (size[0] > kGuaranteedSize[0] || size[1] > kGuaranteedSize[1] || size[2] > kGuaranteedSize[2])
    diag.warning(stage.desc->where,
                 who + " has a work-group size of " + text +
                     ", beyond the maxComputeWorkGroupSize Vulkan guarantees (128, 128, 64): "
                     "devices with lower limits refuse the pipeline");
  else if (size[0] * size[1] * size[2] > kGuaranteedInvocations)
    diag.warning(stage.desc->where, who + " has work groups of " + text + " = " +
                                        std::to_string(size[0] * size[1] * size[2]) +
                                        " invocations, beyond the 128 maxComputeWorkGroupInvocations Vulkan "
                                        "guarantees: devices with lower limits refuse the pipeline");
}

void warn_render_pass_formats(const RenderPassDesc& pass, const SourceTexts& sources, Diagnostics& diag) {
  const format::RenderPass& rp = pass.pass;
  std::set<uint32_t> colors;
  for (const format::Subpass& sp : rp.subpasses)
    for (const format::AttachmentRef& r : sp.colors)
      if (r.attachment < rp.attachments.size()) colors.insert(r.attachment);
  for (uint32_t a : colors) {
    const uint32_t format = rp.attachments[a].format;
    if (format == VK_FORMAT_UNDEFINED || guaranteed_color_attachment(format)) continue;
    diag.warning(
        sources.at(pass.where, pass.where.pointer + "/pAttachments/" + std::to_string(a)),
        "render pass '" + rp.name + "': attachment " + std::to_string(a) + " is " + format_name(format) +
            ", used as a color attachment, which Vulkan does not require devices to support: some devices "
            "will refuse this render pass");
  }
}

}  // namespace statepack::packager
