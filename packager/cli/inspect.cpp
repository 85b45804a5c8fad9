// statepack inspect: every object of an archive, as text or as JSON.
#include "inspect.hpp"

#include "notation/enum_tables.hpp"

#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <nlohmann/json.hpp>
#include <ostream>
#include <vulkan/vulkan.hpp>  // vk::to_string: Vulkan's own enum names, kept up to date by the SDK

#include "format/archive_file.hpp"
#include "format/archive_format.hpp"
#include "format/spirv_walk.hpp"
#include "pack/packer.hpp"
#include "spellings.hpp"
#include "support/printable.hpp"

namespace statepack::packager {
namespace {

using Json = nlohmann::ordered_json;  // keys in insertion order: stable, readable output

std::string version_text(uint32_t v) {
  return std::to_string(v >> 22) + "." + std::to_string((v >> 12) & 0x3FF) + "." + std::to_string(v & 0xFFF);
}
std::string hex64(uint64_t v) {
  char text[19];
  std::snprintf(text, sizeof text, "%016" PRIx64, v);
  return text;
}
// Names come from the archive, which anyone can edit: JSON output replaces bytes that are not UTF-8
// with U+FFFD (nlohmann's error_handler_t::replace), and text output, which goes to terminals, shows
// control characters, backslashes and bytes that are not UTF-8 as \xNN escapes.
std::string printable(const std::string& name) {
  std::string out;
  auto escape = [&](unsigned char c) {
    char text[5];
    std::snprintf(text, sizeof text, "\\x%02X", c);
    out += text;
  };
  for (size_t i = 0; i < name.size();) {
    const auto c = static_cast<unsigned char>(name[i]);
    // Length of a well-formed UTF-8 sequence starting here (RFC 3629: no overlongs, no surrogates).
    size_t length = 0;
    if (c < 0x80) {
      length = 1;
    } else if (c >= 0xC2 && c <= 0xF4) {
      length = c < 0xE0 ? 2 : c < 0xF0 ? 3 : 4;
      if (i + length > name.size()) length = 0;
      for (size_t k = 1; k < length; ++k)
        if ((static_cast<unsigned char>(name[i + k]) & 0xC0) != 0x80) length = 0;
      if (length > 0) {
        const auto c1 = static_cast<unsigned char>(name[i + 1]);
        if ((c == 0xE0 && c1 < 0xA0) || (c == 0xED && c1 > 0x9F) || (c == 0xF0 && c1 < 0x90) ||
            (c == 0xF4 && c1 > 0x8F))
          length = 0;
        // C1 controls (U+0080-U+009F) steer terminals as well as C0 ones do.
        if (c == 0xC2 && c1 < 0xA0) length = 0;
      }
    }
    if (length == 1 && (c < 0x20 || c == 0x7F || c == '\\')) length = 0;
    if (length == 0) {
      escape(c);
      ++i;
    } else {
      out.append(name, i, length);
      i += length;
    }
  }
  return out;
}
std::string text(const Json& value) {
  return printable(value.get<std::string>());
}

std::string none_or(uint32_t index) {
  return index == format::kNone ? "none" : std::to_string(index);
}

// The spellings (spellings.hpp): the notation's names, Vulkan's where the notation has none.
std::string stage_name(uint32_t stage) {
  return notation_name(
      kShaderTypes, stage,
      vulkan_upper_name("VK_SHADER_STAGE_", vk::to_string(vk::ShaderStageFlagBits(stage))) + "_BIT");
}
std::string compare_name(uint32_t op) {
  return notation_name(kComparisonFuncs, op,
                       vulkan_upper_name("VK_COMPARE_OP_", vk::to_string(vk::CompareOp(op))));
}
std::string blend_factor_name(uint32_t factor) {
  return notation_name(kBlendFactors, factor,
                       vulkan_upper_name("VK_BLEND_FACTOR_", vk::to_string(vk::BlendFactor(factor))));
}
std::string blend_op_name(uint32_t op) {
  return notation_name(kBlendOps, op, vulkan_upper_name("VK_BLEND_OP_", vk::to_string(vk::BlendOp(op))));
}
std::string stencil_op_name(uint32_t op) {
  return notation_name(kStencilOps, op,
                       vulkan_upper_name("VK_STENCIL_OP_", vk::to_string(vk::StencilOp(op))));
}
// A format as JSON: the notation's name under `key`, Vulkan's under "vk_" + key.
void put_format(Json& j, const std::string& key, uint32_t format) {
  j[key] = format_name(format);
  j["vk_" + key] = vulkan_format_name(format);
}

Json stages_json(uint32_t flags) {
  Json out = Json::array();
  for (uint32_t bit = 1; bit <= VK_SHADER_STAGE_COMPUTE_BIT; bit <<= 1)
    if (flags & bit) out.push_back(stage_name(bit));
  return out;
}

Json binding_json(const format::Binding& b) {
  Json j;
  j["name"] = b.name;
  j["binding"] = b.binding;
  j["type"] = vulkan_upper_name("VK_DESCRIPTOR_TYPE_", vk::to_string(vk::DescriptorType(b.descriptor_type)));
  j["count"] = b.count;
  j["stages"] = stages_json(b.stage_flags);
  if (b.immutable_sampler != format::kNone) j["immutable_sampler"] = b.immutable_sampler;
  return j;
}

Json graphics_json(const format::Contents& c, const format::Pipeline& p) {
  const format::GraphicsState& g = p.graphics;
  Json j;
  j["topology"] = g.topology == VK_PRIMITIVE_TOPOLOGY_PATCH_LIST
                      ? notation_name(kTopologies, kPatchListTopology + g.patch_control_points,
                                      "VK_PRIMITIVE_TOPOLOGY_PATCH_LIST")
                      : notation_name(kTopologies, g.topology,
                                      vulkan_upper_name("VK_PRIMITIVE_TOPOLOGY_",
                                                        vk::to_string(vk::PrimitiveTopology(g.topology))));
  if (g.patch_control_points != 0) j["patch_control_points"] = g.patch_control_points;
  j["polygon_mode"] =
      notation_name(kFillModes, g.polygon_mode,
                    vulkan_upper_name("VK_POLYGON_MODE_", vk::to_string(vk::PolygonMode(g.polygon_mode))));
  j["cull_mode"] = notation_name(kCullModes, g.cull_mode, "VK_CULL_MODE_FRONT_AND_BACK");
  // The notation says FrontCounterClockwise (a bool), not a name: Vulkan's name of the archived value.
  j["front_face"] = vulkan_upper_name("VK_FRONT_FACE_", vk::to_string(vk::FrontFace(g.front_face)));
  j["depth_test"] = g.depth_test != 0;
  j["depth_write"] = g.depth_write != 0;
  j["depth_compare"] = compare_name(g.depth_compare);
  j["depth_clamp"] = g.depth_clamp != 0;
  j["depth_bias"] = {
      {"constant", g.depth_bias}, {"clamp", g.depth_bias_clamp}, {"slope", g.depth_bias_slope}};
  j["stencil_test"] = g.stencil_test != 0;
  auto stencil_ops = [](const format::StencilOpState& s) {
    return Json{{"fail", stencil_op_name(s.fail_op)},
                {"pass", stencil_op_name(s.pass_op)},
                {"depth_fail", stencil_op_name(s.depth_fail_op)},
                {"compare", compare_name(s.compare_op)}};
  };
  j["stencil"] = {{"read_mask", g.stencil_read_mask},
                  {"write_mask", g.stencil_write_mask},
                  {"front", stencil_ops(g.front)},
                  {"back", stencil_ops(g.back)}};
  j["samples"] = g.samples;
  j["sample_mask"] = g.sample_mask;
  j["alpha_to_coverage"] = g.alpha_to_coverage != 0;
  Json formats = Json::array();
  for (uint32_t i = 0; i < g.color_count; ++i) {
    Json target;
    put_format(target, "format", g.color_formats[i]);
    target["blend"] = g.blend[i].enable != 0;
    {  // factors and ops are stored (and shown) even when blending is off
      target["color"] = blend_factor_name(g.blend[i].src_color) + " " + blend_op_name(g.blend[i].color_op) +
                        " " + blend_factor_name(g.blend[i].dst_color);
      target["alpha"] = blend_factor_name(g.blend[i].src_alpha) + " " + blend_op_name(g.blend[i].alpha_op) +
                        " " + blend_factor_name(g.blend[i].dst_alpha);
    }
    target["write_mask"] = g.blend[i].write_mask;
    formats.push_back(target);
  }
  j["render_targets"] = formats;
  // Targets the pixel shader writes beyond the archive's count: the notation left them to run time.
  Json run_time = Json::array();
  for (uint32_t index : p.shaders) {
    if (index >= c.shaders.size() || c.shaders[index].stage != VK_SHADER_STAGE_FRAGMENT_BIT) continue;
    auto module = spirv::walk(c.spirv.at(c.shaders[index].blob));
    const uint32_t written = module ? module->output_location_mask() : 0;
    for (uint32_t l = g.color_count; l < 32; ++l)
      if (written & (1u << l)) run_time.push_back(l);
  }
  if (!run_time.empty()) j["run_time_render_targets"] = run_time;
  put_format(j, "depth_stencil_format", g.depth_stencil_format);
  Json bindings = Json::array(), attributes = Json::array();
  for (const auto& b : g.vertex_bindings)
    bindings.push_back({{"binding", b.binding},
                        {"stride", b.stride},
                        {"rate", vulkan_upper_name("VK_VERTEX_INPUT_RATE_",
                                                   vk::to_string(vk::VertexInputRate(b.input_rate)))}});
  for (const auto& a : g.vertex_attributes) {
    Json attribute{{"location", a.location}, {"binding", a.binding}};
    put_format(attribute, "format", a.format);
    attribute["offset"] = a.offset;
    attributes.push_back(attribute);
  }
  if (!bindings.empty()) j["vertex_bindings"] = bindings;
  if (!attributes.empty()) j["vertex_attributes"] = attributes;
  j["render_pass"] = p.render_pass == format::kNone ? "none" : c.render_passes[p.render_pass].name;
  if (p.render_pass != format::kNone) j["subpass"] = p.subpass;
  return j;
}

Json sampler_json(const format::Sampler& s) {
  // The notation's names of the plain filters (POINT, LINEAR) and address modes.
  auto filter = [](uint32_t f) {
    return notation_name(kFilterTypes, f, vulkan_upper_name("VK_FILTER_", vk::to_string(vk::Filter(f))));
  };
  auto address = [](uint32_t a) {
    return notation_name(
        kAddressModes, a,
        vulkan_upper_name("VK_SAMPLER_ADDRESS_MODE_", vk::to_string(vk::SamplerAddressMode(a))));
  };
  return {{"filter", filter(s.min_filter) + "/" + filter(s.mag_filter) + "/" +
                         filter(s.mipmap_mode)},  // VK_SAMPLER_MIPMAP_MODE_* has VkFilter's values
          {"address", address(s.address_u) + "/" + address(s.address_v) + "/" + address(s.address_w)},
          {"anisotropy", s.anisotropy_enable ? s.max_anisotropy : 0.0f},
          {"compare", s.compare_enable ? compare_name(s.compare_op) : "none"}};
}

Json render_pass_json(const format::RenderPass& rp) {
  Json pass{{"name", rp.name}};
  Json attachments = Json::array();
  auto load = [](uint32_t op) {
    return notation_name(
        kLoadOps, op, vulkan_upper_name("VK_ATTACHMENT_LOAD_OP_", vk::to_string(vk::AttachmentLoadOp(op))));
  };
  auto store = [](uint32_t op) {
    return notation_name(
        kStoreOps, op,
        vulkan_upper_name("VK_ATTACHMENT_STORE_OP_", vk::to_string(vk::AttachmentStoreOp(op))));
  };
  // Layouts as Vulkan's: the notation's RESOURCE_STATE_* names map several states to one layout.
  auto layout = [](uint32_t l) {
    return vulkan_upper_name("VK_IMAGE_LAYOUT_", vk::to_string(vk::ImageLayout(l)));
  };
  for (const auto& a : rp.attachments) {
    Json attachment;
    put_format(attachment, "format", a.format);
    attachment.update({{"samples", a.samples},
                       {"load", load(a.load_op)},
                       {"store", store(a.store_op)},
                       {"stencil_load", load(a.stencil_load_op)},
                       {"stencil_store", store(a.stencil_store_op)},
                       {"initial_layout", layout(a.initial_layout)},
                       {"final_layout", layout(a.final_layout)}});
    attachments.push_back(attachment);
  }
  pass["attachments"] = attachments;
  Json subpasses = Json::array();
  for (const auto& s : rp.subpasses) {
    auto refs = [](const std::vector<format::AttachmentRef>& list) {
      Json out = Json::array();
      for (const auto& r : list) out.push_back(none_or(r.attachment));
      return out;
    };
    subpasses.push_back({{"inputs", refs(s.inputs)},
                         {"colors", refs(s.colors)},
                         {"resolves", refs(s.resolves)},
                         {"depth_stencil", none_or(s.depth_stencil.attachment)}});
  }
  pass["subpasses"] = subpasses;
  Json dependencies = Json::array();
  auto stage_bit = [](uint32_t bit) {
    return vulkan_upper_name("VK_PIPELINE_STAGE_", vk::to_string(vk::PipelineStageFlagBits(bit))) + "_BIT";
  };
  auto access_bit = [](uint32_t bit) {
    return vulkan_upper_name("VK_ACCESS_", vk::to_string(vk::AccessFlagBits(bit))) + "_BIT";
  };
  for (const auto& d : rp.dependencies)
    dependencies.push_back(
        {{"src_subpass", d.src_subpass == format::kNone ? Json("external") : Json(d.src_subpass)},
         {"dst_subpass", d.dst_subpass == format::kNone ? Json("external") : Json(d.dst_subpass)},
         {"src_stages", notation_flags(kPipelineStages, d.src_stages, stage_bit)},
         {"dst_stages", notation_flags(kPipelineStages, d.dst_stages, stage_bit)},
         {"src_access", notation_flags(kAccessFlags, d.src_access, access_bit)},
         {"dst_access", notation_flags(kAccessFlags, d.dst_access, access_bit)},
         {"flags", d.flags == 0 ? std::string("NONE")
                                : vulkan_upper_name("VK_", vk::to_string(vk::DependencyFlags(d.flags)))}});
  pass["dependencies"] = dependencies;
  return pass;
}

// A specialization constant's value by the type its shader declares (bool, int, uint, float), beside
// its bits; a type the walker does not know shows the bits alone.
void put_constant_value(Json& j, spirv::SpecKind kind, uint32_t size, uint64_t bits) {
  char hex[24];
  std::snprintf(hex, sizeof hex, size == 8 ? "0x%016llx" : "0x%08llx", static_cast<unsigned long long>(bits));
  switch (kind) {
    case spirv::SpecKind::boolean:
      j["type"] = "bool", j["value"] = bits != 0;
      break;
    case spirv::SpecKind::sint:
      j["type"] = size == 8 ? "int64" : "int";
      j["value"] = size == 8 ? static_cast<int64_t>(bits) : int64_t(static_cast<int32_t>(uint32_t(bits)));
      break;
    case spirv::SpecKind::uint:
      j["type"] = size == 8 ? "uint64" : "uint", j["value"] = bits;
      break;
    case spirv::SpecKind::float_: {
      j["type"] = size == 8 ? "double" : "float";
      double value = 0;
      if (size == 8) {
        std::memcpy(&value, &bits, 8);
      } else {
        float f = 0;
        const uint32_t low = uint32_t(bits);
        std::memcpy(&f, &low, 4);
        value = f;
      }
      if (std::isfinite(value)) j["value"] = value;  // JSON has no NaN or infinity: the bits say it
      break;
    }
    case spirv::SpecKind::other:
      break;
  }
  j["bits"] = hex;
}

Json constants_json(const format::Contents& c, const format::Pipeline& p) {
  Json constants = Json::array();
  for (const auto& k : p.constants) {
    Json j{
        {"name", k.name}, {"stage", stage_name(k.stage)}, {"constant_id", k.constant_id}, {"size", k.size}};
    spirv::SpecKind kind = spirv::SpecKind::other;
    for (uint32_t index : p.shaders)
      if (index < c.shaders.size() && c.shaders[index].stage == k.stage)
        if (auto module = spirv::walk(c.spirv.at(c.shaders[index].blob)))
          if (const spirv::SpecConstant* declared = module->find_spec_constant(k.constant_id))
            kind = declared->kind;
    put_constant_value(j, kind, k.size, k.value);
    constants.push_back(j);
  }
  return constants;
}

Json pipeline_json(const format::Contents& c, const format::Pipeline& p) {
  Json pj{{"name", p.name}, {"kind", p.kind == format::PipelineKind::compute ? "compute" : "graphics"}};
  Json stages = Json::array();
  for (uint32_t s : p.shaders)
    stages.push_back({{"stage", stage_name(c.shaders[s].stage)},
                      {"shader", c.shaders[s].name},
                      {"size", c.spirv[c.shaders[s].blob].size_bytes()}});
  pj["shaders"] = stages;
  Json sets = Json::array();
  for (uint32_t set = 0; set < p.set_layouts.size(); ++set) {
    Json sj{{"set", set}};
    if (p.set_layouts[set] != format::kNone) {
      const auto& layout = c.set_layouts[p.set_layouts[set]];
      if (!layout.name.empty()) sj["signature"] = layout.name;
      Json bindings = Json::array();
      for (const auto& b : layout.bindings) bindings.push_back(binding_json(b));
      sj["bindings"] = bindings;
    }
    sets.push_back(sj);
  }
  pj["sets"] = sets;
  if (p.push_constant_size)
    pj["push_constants"] = {{"size", p.push_constant_size}, {"stages", stages_json(p.push_constant_stages)}};
  if (p.kind == format::PipelineKind::graphics) {
    pj["graphics"] = graphics_json(c, p);
    Json dynamic = Json::array();
    for (const auto& [name, bit] : kDynamicStates)
      if (bit != kUnsupportedValue && (p.dynamic_states & bit)) dynamic.push_back(name);
    pj["dynamic_states"] = dynamic;
  }
  if (!p.constants.empty()) pj["specialization_constants"] = constants_json(c, p);
  return pj;
}

// An OpenGL pipeline: its own shaders and binding table, the same graphics state as Vulkan's.
Json gl_pipeline_json(const format::Contents& c, const format::GlPipeline& p) {
  Json pj{{"name", p.name}, {"kind", p.kind == format::PipelineKind::compute ? "compute" : "graphics"}};
  Json gl_shaders = Json::array();
  for (const auto& s : p.shaders)
    gl_shaders.push_back({{"stage", stage_name(s.stage)},
                          {"shader", s.name},
                          {"entry_point", s.entry_point},
                          {"blob", s.blob},
                          {"size", c.spirv[s.blob].size_bytes()}});
  pj["shaders"] = gl_shaders;
  Json bindings = Json::array();
  for (const auto& b : p.bindings)
    bindings.push_back({{"name", b.name},
                        {"kind", format::gl_namespace_name(b.kind)},
                        {"binding", b.binding},
                        {"count", b.count},
                        {"stages", stages_json(b.stages)}});
  pj["bindings"] = bindings;
  if (p.kind == format::PipelineKind::graphics) {
    format::Pipeline as_vulkan;  // the same state, printed the same way (no render pass in OpenGL)
    as_vulkan.graphics = p.graphics;
    pj["graphics"] = graphics_json(c, as_vulkan);
    pj["graphics"].erase("render_pass");
  }
  Json constants = Json::array();
  for (const auto& k : p.constants)
    constants.push_back(
        {{"name", k.name}, {"stage", stage_name(k.stage)}, {"constant_id", k.constant_id}, {"size", k.size}});
  if (!constants.empty()) pj["specialization_constants"] = constants;
  return pj;
}

Json contents_json(const format::Contents& c, size_t size) {
  Json j;
  j["format_version"] = c.format_version;
  j["producer_version"] = version_text(c.producer_version);
  j["content_version"] = c.content_version;
  j["backends"] = Json::array();
  if (c.backends & format::kBackendVulkan) j["backends"].push_back("vulkan");
  if (c.backends & format::kBackendOpenGL) j["backends"].push_back("opengl");
  j["size"] = size;
  Json blobs = Json::array();
  for (auto blob : c.spirv)
    blobs.push_back({{"size", blob.size_bytes()},
                     {"xxh3", hex64(format::hash_bytes(
                                  {reinterpret_cast<const uint8_t*>(blob.data()), blob.size_bytes()}))}});
  j["spirv_blobs"] = blobs;
  Json shaders = Json::array();
  for (const auto& s : c.shaders)
    shaders.push_back(
        {{"name", s.name}, {"stage", stage_name(s.stage)}, {"entry_point", s.entry_point}, {"blob", s.blob}});
  j["shaders"] = shaders;
  Json standalone = Json::array();
  for (uint32_t s : c.standalone_shaders) standalone.push_back(c.shaders[s].name);
  j["standalone_shaders"] = standalone;
  Json samplers = Json::array();
  for (const auto& s : c.samplers) samplers.push_back(sampler_json(s));
  j["samplers"] = samplers;
  Json signatures = Json::array();
  for (const auto& l : c.set_layouts) {
    if (l.name.empty()) continue;
    Json sig{{"name", l.name}, {"set", l.binding_index}};
    Json bindings = Json::array();
    for (const auto& b : l.bindings) bindings.push_back(binding_json(b));
    sig["bindings"] = bindings;
    signatures.push_back(sig);
  }
  j["resource_signatures"] = signatures;
  Json passes = Json::array();
  for (const auto& rp : c.render_passes) passes.push_back(render_pass_json(rp));
  j["render_passes"] = passes;
  Json pipelines = Json::array();
  for (const auto& p : c.pipelines) pipelines.push_back(pipeline_json(c, p));
  j["pipelines"] = pipelines;
  // The OpenGL block, only when present (Vulkan-only archives print as before).
  if (!c.gl_pipelines.empty()) {
    Json gl = Json::array();
    for (const auto& p : c.gl_pipelines) gl.push_back(gl_pipeline_json(c, p));
    j["opengl_pipelines"] = gl;
  }
  return j;
}

// A format in text: the notation's name with Vulkan's in parentheses (put_format wrote both).
std::string format_text(const Json& j, const std::string& key) {
  return j[key].get<std::string>() + " (" + j["vk_" + key].get<std::string>() + ")";
}

// A Vulkan pipeline's graphics state: the summary line, then raster, depth, stencil, multisample and
// each target's blend.
void print_graphics_text(const Json& g, std::ostream& out) {
  out << "  " << g["topology"].get<std::string>();
  if (g.contains("patch_control_points")) out << " of " << g["patch_control_points"].get<uint32_t>();
  out << ", cull " << g["cull_mode"].get<std::string>() << ", depth test "
      << (g["depth_test"].get<bool>() ? "on" : "off") << ", targets:";
  for (const auto& t : g["render_targets"])
    out << " "
        << (t["vk_format"] == "VK_FORMAT_UNDEFINED" ? std::string("UNKNOWN (set at unpack)")
                                                    : format_text(t, "format"));
  if (g.contains("run_time_render_targets")) {
    out << " + set at run time:";
    for (const auto& l : g["run_time_render_targets"]) out << " " << l.get<uint32_t>();
  }
  if (g["render_pass"] != "none") out << ", render pass '" << text(g["render_pass"]) << "'";
  out << "\n";
  out << "    raster: " << g["polygon_mode"].get<std::string>() << ", front face "
      << g["front_face"].get<std::string>() << ", depth clamp "
      << (g["depth_clamp"].get<bool>() ? "on" : "off") << ", depth bias "
      << g["depth_bias"]["constant"].get<float>() << " (clamp " << g["depth_bias"]["clamp"].get<float>()
      << ", slope " << g["depth_bias"]["slope"].get<float>() << ")\n";
  out << "    depth: write " << (g["depth_write"].get<bool>() ? "on" : "off") << ", compare "
      << g["depth_compare"].get<std::string>() << ", format " << format_text(g, "depth_stencil_format")
      << "\n";
  const auto& st = g["stencil"];
  auto ops = [](const Json& s) {
    return s["compare"].get<std::string>() + " fail " + s["fail"].get<std::string>() + " pass " +
           s["pass"].get<std::string>() + " depth-fail " + s["depth_fail"].get<std::string>();
  };
  out << "    stencil: " << (g["stencil_test"].get<bool>() ? "on" : "off") << ", read mask 0x" << std::hex
      << st["read_mask"].get<uint32_t>() << ", write mask 0x" << st["write_mask"].get<uint32_t>() << std::dec
      << ", front " << ops(st["front"]) << ", back " << ops(st["back"]) << "\n";
  out << "    multisample: " << g["samples"].get<uint32_t>() << " sample(s), mask 0x" << std::hex
      << g["sample_mask"].get<uint32_t>() << std::dec << ", alpha to coverage "
      << (g["alpha_to_coverage"].get<bool>() ? "on" : "off") << "\n";
  for (size_t i = 0; i < g["render_targets"].size(); ++i) {
    const auto& t = g["render_targets"][i];
    out << "    target " << i << ": blend " << (t["blend"].get<bool>() ? "on" : "off") << ", color "
        << t["color"].get<std::string>() << ", alpha " << t["alpha"].get<std::string>() << ", write mask 0x"
        << std::hex << t["write_mask"].get<uint32_t>() << std::dec << "\n";
  }
}

void print_pipeline_text(const Json& p, std::ostream& out) {
  out << "pipeline '" << text(p["name"]) << "' (" << p["kind"].get<std::string>() << ")\n";
  for (const auto& s : p["shaders"])
    out << "  " << s["stage"].get<std::string>() << ": '" << text(s["shader"]) << "', "
        << s["size"].get<size_t>() << " bytes\n";
  for (const auto& set : p["sets"]) {
    if (!set.contains("bindings")) continue;
    out << "  set " << set["set"].get<uint32_t>();
    if (set.contains("signature")) out << " (signature '" << text(set["signature"]) << "')";
    out << "\n";
    for (const auto& b : set["bindings"])
      out << "    binding " << b["binding"].get<uint32_t>() << ": '" << text(b["name"]) << "' "
          << b["type"].get<std::string>() << " x" << b["count"].get<uint32_t>() << " " << b["stages"].dump()
          << (b.contains("immutable_sampler")
                  ? ", immutable sampler " + std::to_string(b["immutable_sampler"].get<uint32_t>())
                  : std::string())
          << "\n";
  }
  if (p.contains("push_constants"))
    out << "  push constants: " << p["push_constants"]["size"].get<uint32_t>() << " bytes\n";
  if (p.contains("specialization_constants"))
    for (const auto& k : p["specialization_constants"])
      out << "  specialization constant '" << text(k["name"]) << "' (" << k["stage"].get<std::string>()
          << ", id " << k["constant_id"].get<uint32_t>() << ", "
          << (k.contains("type") ? k["type"].get<std::string>()
                                 : std::to_string(k["size"].get<uint32_t>()) + " bytes")
          << ") = " << (k.contains("value") ? k["value"].dump() : k["bits"].get<std::string>()) << "\n";
  if (p.contains("dynamic_states")) {
    out << "  dynamic:";
    for (const auto& d : p["dynamic_states"]) out << " " << d.get<std::string>();
    out << "\n";
  }
  if (p.contains("graphics")) print_graphics_text(p["graphics"], out);
}

void print_render_pass_text(const Json& r, std::ostream& out) {
  out << "render pass '" << text(r["name"]) << "' (" << r["attachments"].size() << " attachments, "
      << r["subpasses"].size() << " subpasses)\n";
  for (size_t i = 0; i < r["attachments"].size(); ++i) {
    const auto& a = r["attachments"][i];
    out << "  attachment " << i << ": " << format_text(a, "format") << " x" << a["samples"].get<uint32_t>()
        << ", " << a["load"].get<std::string>() << "/" << a["store"].get<std::string>() << ", stencil "
        << a["stencil_load"].get<std::string>() << "/" << a["stencil_store"].get<std::string>() << ", "
        << a["initial_layout"].get<std::string>() << " -> " << a["final_layout"].get<std::string>() << "\n";
  }
  auto subpass = [](const Json& s) { return s.is_string() ? s.get<std::string>() : s.dump(); };
  for (const auto& d : r["dependencies"])
    out << "  dependency " << subpass(d["src_subpass"]) << " -> " << subpass(d["dst_subpass"]) << ": stages "
        << d["src_stages"].get<std::string>() << " -> " << d["dst_stages"].get<std::string>() << ", access "
        << d["src_access"].get<std::string>() << " -> " << d["dst_access"].get<std::string>() << "\n";
}

void print_gl_pipeline_text(const Json& p, std::ostream& out) {
  out << "OpenGL pipeline '" << text(p["name"]) << "' (" << p["kind"].get<std::string>() << ")\n";
  for (const auto& s : p["shaders"])
    out << "  " << s["stage"].get<std::string>() << ": '" << text(s["shader"]) << "', "
        << s["size"].get<size_t>() << " bytes (blob " << s["blob"].get<uint32_t>() << ")\n";
  for (const auto& b : p["bindings"])
    out << "  " << b["kind"].get<std::string>() << " " << b["binding"].get<uint32_t>() << ": '"
        << text(b["name"]) << "' x" << b["count"].get<uint32_t>() << " " << b["stages"].dump() << "\n";
  if (p.contains("graphics")) {
    const auto& g = p["graphics"];
    out << "  " << g["topology"].get<std::string>() << ", cull " << g["cull_mode"].get<std::string>()
        << ", front face " << g["front_face"].get<std::string>() << ", depth test "
        << (g["depth_test"].get<bool>() ? "on" : "off") << ", " << g["render_targets"].size()
        << " target(s)\n";
  }
}

void print_text(const Json& j, std::ostream& out) {
  out << "format v" << j["format_version"].get<uint32_t>() << ", made by statepack "
      << j["producer_version"].get<std::string>() << ", content version "
      << j["content_version"].get<uint32_t>() << ", " << j["size"].get<size_t>()
      << " bytes, backends: " << j["backends"].dump() << "\n";
  out << j["spirv_blobs"].size() << " SPIR-V blob(s), " << j["shaders"].size() << " shader record(s), "
      << j["samplers"].size() << " sampler(s)\n";
  // The blob table's sizes and content hashes (decode checked each hash against its bytes).
  for (size_t i = 0; i < j["spirv_blobs"].size(); ++i)
    out << "  SPIR-V blob " << i << ": " << j["spirv_blobs"][i]["size"].get<size_t>() << " bytes, XXH3 "
        << j["spirv_blobs"][i]["xxh3"].get<std::string>() << "\n";
  // The samplers immutable bindings name by index ("immutable sampler 0").
  for (size_t i = 0; i < j["samplers"].size(); ++i) {
    const Json& s = j["samplers"][i];
    out << "  sampler " << i << ": filter " << s["filter"].get<std::string>() << ", address "
        << s["address"].get<std::string>() << ", anisotropy " << s["anisotropy"].get<float>() << ", compare "
        << s["compare"].get<std::string>() << "\n";
  }
  for (const auto& p : j["pipelines"]) print_pipeline_text(p, out);
  for (const auto& s : j["resource_signatures"])
    out << "resource signature '" << text(s["name"]) << "' (set " << s["set"].get<uint32_t>() << ", "
        << s["bindings"].size() << " bindings)\n";
  for (const auto& r : j["render_passes"]) print_render_pass_text(r, out);
  for (const auto& s : j["standalone_shaders"]) out << "standalone shader '" << text(s) << "'\n";
  if (j.contains("opengl_pipelines"))
    for (const auto& p : j["opengl_pipelines"]) print_gl_pipeline_text(p, out);
}

}  // namespace

int run_inspect(const std::string& path, bool as_json, std::ostream& out, std::ostream& err) {
  auto archive = format::load_archive_file_with_opengl(path);
  if (!archive) {
    err << "statepack: error: " << detail::printable(archive.error().message) << '\n';
    return archive.error().code == ErrorCode::io_error ? kExitIoError : kExitInputError;
  }
  std::error_code ec;
  print_archive(archive->contents, static_cast<size_t>(std::filesystem::file_size(path, ec)), as_json, out);
  return kExitSuccess;
}

void print_archive(const format::Contents& contents, size_t size, bool as_json, std::ostream& out) {
  Json j = contents_json(contents, size);
  if (as_json)
    out << j.dump(2, ' ', false, Json::error_handler_t::replace) << '\n';
  else
    print_text(j, out);
}

}  // namespace statepack::packager
