#include "notation_objects.hpp"

#include "notation_schema.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cfloat>
#include <map>
#include <set>

namespace statepack::packager {
namespace fs = std::filesystem;
namespace {

SourceLanguage language_from_extension(const std::string& path) {
  static const char* kGlsl[] = {".glsl", ".vert", ".frag", ".comp", ".geom", ".tesc", ".tese"};
  std::string ext = fs::path(path).extension().string();
  for (const char* e : kGlsl)
    if (ext == e) return SourceLanguage::glsl;
  return SourceLanguage::hlsl;  // Diligent's DEFAULT means HLSL
}

std::optional<uint32_t> parse_index(JsonReader& json, const std::string& key, const std::string& pointer) {
  if (key.size() == 1 && key[0] >= '0' && key[0] < '0' + int(format::kMaxColorTargets))
    return static_cast<uint32_t>(key[0] - '0');
  json.diagnostics().error(json.at_key(pointer + "/" + key),
                           "render-target index '" + key + "' must be \"0\" to \"7\"");
  return std::nullopt;
}

// (value type, component count, normalized) -> VkFormat; 0 when Vulkan has none.
uint32_t vertex_format(uint32_t value_type, uint32_t components, bool normalized) {
  // Rows: VALUE_TYPE 1..8 (INT8 .. FLOAT32); columns: 1..4 components; [0] integer, [1] normalized.
  static constexpr uint32_t kFormats[8][2][4] = {
      {{VK_FORMAT_R8_SINT, VK_FORMAT_R8G8_SINT, VK_FORMAT_R8G8B8_SINT, VK_FORMAT_R8G8B8A8_SINT},
       {VK_FORMAT_R8_SNORM, VK_FORMAT_R8G8_SNORM, VK_FORMAT_R8G8B8_SNORM, VK_FORMAT_R8G8B8A8_SNORM}},
      {{VK_FORMAT_R16_SINT, VK_FORMAT_R16G16_SINT, VK_FORMAT_R16G16B16_SINT, VK_FORMAT_R16G16B16A16_SINT},
       {VK_FORMAT_R16_SNORM, VK_FORMAT_R16G16_SNORM, VK_FORMAT_R16G16B16_SNORM,
        VK_FORMAT_R16G16B16A16_SNORM}},
      {{VK_FORMAT_R32_SINT, VK_FORMAT_R32G32_SINT, VK_FORMAT_R32G32B32_SINT, VK_FORMAT_R32G32B32A32_SINT},
       {VK_FORMAT_R32_SINT, VK_FORMAT_R32G32_SINT, VK_FORMAT_R32G32B32_SINT, VK_FORMAT_R32G32B32A32_SINT}},
      {{VK_FORMAT_R8_UINT, VK_FORMAT_R8G8_UINT, VK_FORMAT_R8G8B8_UINT, VK_FORMAT_R8G8B8A8_UINT},
       {VK_FORMAT_R8_UNORM, VK_FORMAT_R8G8_UNORM, VK_FORMAT_R8G8B8_UNORM, VK_FORMAT_R8G8B8A8_UNORM}},
      {{VK_FORMAT_R16_UINT, VK_FORMAT_R16G16_UINT, VK_FORMAT_R16G16B16_UINT, VK_FORMAT_R16G16B16A16_UINT},
       {VK_FORMAT_R16_UNORM, VK_FORMAT_R16G16_UNORM, VK_FORMAT_R16G16B16_UNORM,
        VK_FORMAT_R16G16B16A16_UNORM}},
      {{VK_FORMAT_R32_UINT, VK_FORMAT_R32G32_UINT, VK_FORMAT_R32G32B32_UINT, VK_FORMAT_R32G32B32A32_UINT},
       {VK_FORMAT_R32_UINT, VK_FORMAT_R32G32_UINT, VK_FORMAT_R32G32B32_UINT, VK_FORMAT_R32G32B32A32_UINT}},
      {{VK_FORMAT_R16_SFLOAT, VK_FORMAT_R16G16_SFLOAT, VK_FORMAT_R16G16B16_SFLOAT,
        VK_FORMAT_R16G16B16A16_SFLOAT},
       {VK_FORMAT_R16_SFLOAT, VK_FORMAT_R16G16_SFLOAT, VK_FORMAT_R16G16B16_SFLOAT,
        VK_FORMAT_R16G16B16A16_SFLOAT}},
      {{VK_FORMAT_R32_SFLOAT, VK_FORMAT_R32G32_SFLOAT, VK_FORMAT_R32G32B32_SFLOAT,
        VK_FORMAT_R32G32B32A32_SFLOAT},
       {VK_FORMAT_R32_SFLOAT, VK_FORMAT_R32G32_SFLOAT, VK_FORMAT_R32G32B32_SFLOAT,
        VK_FORMAT_R32G32B32A32_SFLOAT}},
  };
  if (value_type < 1 || value_type > 8 || components < 1 || components > 4) return 0;
  return kFormats[value_type - 1][normalized ? 1 : 0][components - 1];
}

uint32_t component_size(uint32_t value_type) {
  static constexpr uint32_t kSizes[] = {0, 1, 2, 4, 1, 2, 4, 2, 4};
  return value_type < 9 ? kSizes[value_type] : 0;
}

void read_input_layout(ReadContext& ctx, const Json& j, const std::string& pointer, format::GraphicsState& g,
                       std::vector<std::string>& semantics) {
  JsonReader& json = ctx.json;
  if (!json.expect_object(j, pointer, "'InputLayout'")) return;
  json.check_keys(j, pointer, schema::kInputLayout, "InputLayout");
  auto elements = j.find("LayoutElements");
  if (elements == j.end() || !json.expect_array(*elements, pointer + "/LayoutElements", "'LayoutElements'"))
    return;
  constexpr uint32_t kAuto = 0xFFFFFFFFu;
  std::map<uint32_t, uint32_t> slot_size;        // buffer slot -> running offset
  std::map<uint32_t, uint32_t> explicit_stride;  // buffer slot -> Stride given
  std::map<uint32_t, uint32_t> slot_rate;
  g.vertex_attributes.clear();
  g.vertex_bindings.clear();
  semantics.clear();
  for (size_t i = 0; i < elements->size(); ++i) {
    std::string ep = pointer + "/LayoutElements/" + std::to_string(i);
    const Json& e = (*elements)[i];
    if (!json.expect_object(e, ep, "a layout element")) continue;
    json.check_keys(e, ep, schema::kLayoutElement, "layout element");
    uint32_t location = 0, slot = 0, components = 0, value_type = 8, normalized = 1, offset = kAuto,
             stride = kAuto, rate = VK_VERTEX_INPUT_RATE_VERTEX, step = 1;
    // Diligent's Vulkan backend reads an HLSL input of semantic ATTRIBn at location n; another name is
    // matched as Direct3D matches it (the semantic with InputIndex), at pack time
    // (layout/vertex_semantics.hpp).
    std::string semantic = json.string(e, "HLSLSemantic", ep).value_or("ATTRIB");
    if (semantic.empty() || !std::all_of(semantic.begin(), semantic.end(), [](char c) {
          return std::isalnum(static_cast<unsigned char>(c)) || c == '_';
        })) {
      json.error(ep + "/HLSLSemantic", "'HLSLSemantic' must be a semantic name (letters, digits, '_')");
      semantic = "ATTRIB";
    }
    json.unsigned_number(e, "InputIndex", ep, location);
    json.unsigned_number(e, "BufferSlot", ep, slot);
    json.unsigned_number(e, "NumComponents", ep, components);
    json.enum_field(e, "ValueType", ep, kValueTypes, "value type", value_type);
    json.boolean(e, "IsNormalized", ep, normalized);
    json.unsigned_number(e, "RelativeOffset", ep, offset);
    json.unsigned_number(e, "Stride", ep, stride);
    json.enum_field(e, "Frequency", ep, kInputFrequencies, "input frequency", rate);
    json.unsigned_number(e, "InstanceDataStepRate", ep, step);
    if (components < 1 || components > 4) {
      json.error(ep, "'NumComponents' must be 1 to 4");
      continue;
    }
    if (step != 1 && rate == VK_VERTEX_INPUT_RATE_INSTANCE)  // per vertex, Diligent ignores it too
      json.error(ep + "/InstanceDataStepRate", "instance step rates other than 1 are not supported");
    uint32_t& running = slot_size[slot];
    if (offset == kAuto) offset = running;
    running = std::max(running, offset + components * component_size(value_type));
    if (stride != kAuto) {
      auto [it, inserted] = explicit_stride.emplace(slot, stride);
      if (!inserted && it->second != stride)
        json.error(ep + "/Stride", "buffer slot " + std::to_string(slot) + " has two different strides");
    }
    auto [rate_it, new_slot] = slot_rate.emplace(slot, rate);
    if (!new_slot && rate_it->second != rate)
      json.error(ep + "/Frequency",
                 "buffer slot " + std::to_string(slot) + " mixes per-vertex and per-instance data");
    g.vertex_attributes.push_back(
        {location, slot, vertex_format(value_type, components, normalized != 0), offset});
    semantics.push_back(std::move(semantic));
  }
  for (const auto& [slot, size] : slot_size) {
    auto stride = explicit_stride.find(slot);
    g.vertex_bindings.push_back(
        {slot, stride != explicit_stride.end() ? stride->second : size, slot_rate[slot]});
  }
}

// An enum of a state that is off: its UNDEFINED (or UNKNOWN) is Diligent's "not set", which Diligent
// replaces with its default (Correct*Desc) instead of refusing it; so does statepack (the default stays).
void enum_unless_unset(JsonReader& json, const Json& object, const char* key, const std::string& pointer,
                       EnumTable table, const char* name, uint32_t& out, bool enabled) {
  if (auto it = object.find(key);
      !enabled && it != object.end() && it->is_string() && (*it == "UNDEFINED" || *it == "UNKNOWN"))
    return;
  json.enum_field(object, key, pointer, table, name, out);
}

void read_blend(ReadContext& ctx, const Json& b, const std::string& pointer, format::GraphicsState& g) {
  JsonReader& json = ctx.json;
  json.check_keys(b, pointer, schema::kBlendDesc, "BlendDesc");
  json.boolean(b, "AlphaToCoverageEnable", pointer, g.alpha_to_coverage);
  uint32_t independent = 0;
  json.boolean(b, "IndependentBlendEnable", pointer, independent);
  auto rts = b.find("RenderTargets");
  if (rts != b.end() &&
      json.expect_object(*rts, pointer + "/RenderTargets", "'RenderTargets' (keyed by index)")) {
    for (const auto& [key, rt] : rts->items()) {
      auto index = parse_index(json, key, pointer + "/RenderTargets");
      std::string rp = pointer + "/RenderTargets/" + key;
      if (!index || !json.expect_object(rt, rp, "a render-target blend description")) continue;
      json.check_keys(rt, rp, schema::kRenderTargetBlend, "render-target blend");
      format::BlendAttachment& a = g.blend[*index];
      json.boolean(rt, "BlendEnable", rp, a.enable);
      uint32_t logic = 0;
      json.boolean(rt, "LogicOperationEnable", rp, logic);
      if (logic)
        json.error(rp + "/LogicOperationEnable", "logic operations are not supported by statepack yet");
      const bool on = a.enable != 0;
      enum_unless_unset(json, rt, "SrcBlend", rp, kBlendFactors, "blend factor", a.src_color, on);
      enum_unless_unset(json, rt, "DestBlend", rp, kBlendFactors, "blend factor", a.dst_color, on);
      enum_unless_unset(json, rt, "BlendOp", rp, kBlendOps, "blend operation", a.color_op, on);
      enum_unless_unset(json, rt, "SrcBlendAlpha", rp, kBlendFactors, "blend factor", a.src_alpha, on);
      enum_unless_unset(json, rt, "DestBlendAlpha", rp, kBlendFactors, "blend factor", a.dst_alpha, on);
      enum_unless_unset(json, rt, "BlendOpAlpha", rp, kBlendOps, "blend operation", a.alpha_op, on);
      json.flags_field(rt, "RenderTargetWriteMask", rp, kColorMasks, "color mask", a.write_mask);
    }
  }
  // Without independent blending every target blends as target 0 does, but keeps its own write mask, as
  // Diligent's Vulkan backend sets it ("even if blend is disabled").
  if (!independent)
    for (size_t i = 1; i < g.blend.size(); ++i) {
      const uint32_t mask = g.blend[i].write_mask;
      g.blend[i] = g.blend[0];
      g.blend[i].write_mask = mask;
    }
}

bool is_depth_stencil_format(uint32_t format) {
  switch (format) {
    case VK_FORMAT_D16_UNORM:
    case VK_FORMAT_X8_D24_UNORM_PACK32:
    case VK_FORMAT_D32_SFLOAT:
    case VK_FORMAT_S8_UINT:
    case VK_FORMAT_D16_UNORM_S8_UINT:
    case VK_FORMAT_D24_UNORM_S8_UINT:
    case VK_FORMAT_D32_SFLOAT_S8_UINT:
      return true;
    default:
      return false;
  }
}

// A shader's Desc: its name, stage (which must match the slot's) and combined-sampler suffix.
void read_shader_desc(JsonReader& json, const Json& desc, const std::string& pointer, uint32_t slot_stage,
                      ShaderDesc& shader) {
  if (!json.expect_object(desc, pointer, "'Desc'")) return;
  json.check_keys(desc, pointer, schema::kShaderDesc, "shader Desc");
  shader.name = json.string(desc, "Name", pointer).value_or("");
  uint32_t combined = 0;
  json.boolean(desc, "UseCombinedTextureSamplers", pointer, combined);
  const std::string suffix = json.string(desc, "CombinedSamplerSuffix", pointer).value_or("_sampler");
  if (combined) shader.combined_sampler_suffix = suffix.empty() ? "_sampler" : suffix;
  if (auto type = desc.find("ShaderType"); type != desc.end()) {
    if (auto stage = json.enum_value(*type, pointer + "/ShaderType", kShaderTypes, "shader type")) {
      if (slot_stage != 0 && *stage != slot_stage)
        json.error(pointer + "/ShaderType", "the shader type does not match the pipeline slot it is in");
      shader.stage = *stage;
    }
  }
}

void read_macros(JsonReader& json, const Json& macros, const std::string& pointer, ShaderDesc& shader) {
  if (!json.expect_array(macros, pointer, "'Macros'")) return;
  for (size_t i = 0; i < macros.size(); ++i) {
    std::string mp = pointer + "/" + std::to_string(i);
    const Json& m = macros[i];
    if (!json.expect_object(m, mp, "a macro")) continue;
    json.check_keys(m, mp, schema::kMacro, "macro");
    auto name = json.string(m, "Name", mp);
    if (!name || name->empty()) {
      json.error(mp, "a macro needs a 'Name'");
      continue;
    }
    shader.macros.emplace_back(*name, json.string(m, "Definition", mp).value_or(""));
    shader.macro_where.push_back(json.at(mp));
  }
}

// A {Major, Minor} version object; nullopt when absent or wrong (reported).
std::optional<std::pair<uint32_t, uint32_t>> read_version(JsonReader& json, const Json& j, const char* key,
                                                          const std::string& pointer) {
  auto it = j.find(key);
  const std::string vp = pointer + "/" + key;
  if (it == j.end() || !json.expect_object(*it, vp, key)) return std::nullopt;
  json.check_keys(*it, vp, schema::kShaderVersion, "shader version");
  uint32_t major = 0, minor = 0;
  json.unsigned_number(*it, "Major", vp, major);
  json.unsigned_number(*it, "Minor", vp, minor);
  return std::pair{major, minor};
}

// CompileFlags, GLSLExtensions, the language versions and ShaderOptimizationLevel: each either does what
// it does in Diligent's Vulkan backend, or means nothing for a Vulkan module (docs/notation.md).
void read_compile_settings(JsonReader& json, const Json& j, const std::string& pointer, ShaderDesc& shader) {
  json.flags_field(j, "CompileFlags", pointer, kCompileFlags, "shader compile flag", shader.compile_flags);
  const bool bytecode = shader.language == SourceLanguage::spirv;
  if (bytecode && (shader.compile_flags & (kPackMatrixRowMajor | kHlslToSpirvViaGlsl)))
    json.error(pointer + "/CompileFlags", "shader '" + shader.name +
                                              "': PACK_MATRIX_ROW_MAJOR and HLSL_TO_SPIRV_VIA_GLSL are "
                                              "compile flags, and BYTECODE is not compiled: a SPIR-V "
                                              "module's matrices are laid out as its compiler decided");
  if ((shader.compile_flags & kHlslToSpirvViaGlsl) && shader.language == SourceLanguage::glsl)
    json.error(pointer + "/CompileFlags",
               "shader '" + shader.name + "': HLSL_TO_SPIRV_VIA_GLSL applies to HLSL sources only");
  else if ((shader.compile_flags & kHlslToSpirvViaGlsl) && shader.language == SourceLanguage::hlsl)
    json.warning(
        pointer + "/CompileFlags",
        "shader '" + shader.name +
            "': HLSL_TO_SPIRV_VIA_GLSL: statepack compiles HLSL with glslang's HLSL front end, not "
            "through Diligent's HLSL-to-GLSL converter: the shader computes the same, but its "
            "descriptors are glslang's (a texture and its sampler stay two) and its entry point keeps "
            "its name");
  if (auto extensions = json.string(j, "GLSLExtensions", pointer)) {
    if (shader.language == SourceLanguage::glsl && !shader.verbatim) {
      shader.glsl_extensions = *extensions;
      shader.extensions_where = json.at(pointer + "/GLSLExtensions");
    } else if (!extensions->empty())  // Diligent ignores it there too: say so rather than drop it silently
      json.warning(pointer + "/GLSLExtensions",
                   "'GLSLExtensions' applies to GLSL sources (not GLSL_VERBATIM, HLSL or BYTECODE), as in "
                   "Diligent; it is ignored here");
  }
  if (auto version = read_version(json, j, "GLSLVersion", pointer)) {
    const uint32_t v = version->first * 100 + version->second * 10;
    static constexpr uint32_t kDesktopVersions[] = {0,   110, 120, 130, 140, 150, 330,
                                                    400, 410, 420, 430, 440, 450, 460};
    if (std::find(std::begin(kDesktopVersions), std::end(kDesktopVersions), v) == std::end(kDesktopVersions))
      json.error(pointer + "/GLSLVersion", "GLSL " + std::to_string(version->first) + "." +
                                               std::to_string(version->second) +
                                               " does not exist (desktop GLSL is 1.10 to 4.60)");
    else if (v != 0 && v < 140 && shader.language == SourceLanguage::glsl && !shader.verbatim)
      json.error(pointer + "/GLSLVersion", "shader '" + shader.name + "': GLSL " +
                                               std::to_string(version->first) + "." +
                                               std::to_string(version->second) +
                                               " cannot be compiled for Vulkan (GL_KHR_vulkan_glsl needs "
                                               "1.40 or later)");
    else if (shader.language == SourceLanguage::glsl && !shader.verbatim)
      shader.glsl_version = v;
  }
  read_version(json, j, "HLSLVersion", pointer);    // DXC's shader model; glslang has none
  read_version(json, j, "GLESSLVersion", pointer);  // OpenGL ES and mobile Vulkan
  read_version(json, j, "MSLVersion", pointer);     // Metal
  // Diligent's SHADER_OPTIMIZATION_LEVEL (an integer in the notation): DEFAULT 0, DISABLED 1,
  // LEVEL_0..LEVEL_3 2..5. Only DISABLED means something to glslang's pipeline, in Diligent as here.
  uint32_t level = 0;
  json.unsigned_number(j, "ShaderOptimizationLevel", pointer, level);
  if (level > 5)
    json.error(pointer + "/ShaderOptimizationLevel",
               "'ShaderOptimizationLevel' is 0 (DEFAULT), 1 (DISABLED) or 2 to 5 (LEVEL_0 to LEVEL_3)");
  shader.optimize = level != 1;
}

}  // namespace

std::optional<ShaderDesc> read_shader(ReadContext& ctx, const Json& j, const std::string& pointer,
                                      uint32_t slot_stage) {
  JsonReader& json = ctx.json;
  ShaderDesc shader;
  shader.where = json.at(pointer);
  shader.stage = slot_stage;
  if (!json.expect_object(j, pointer, slot_stage ? "a shader slot (a name or an object)" : "a shader"))
    return std::nullopt;
  // Counted from before the key check: a misspelt key ("EntryPont") leaves a default where the user
  // meant a value, so the shader is not compiled on that guess.
  const size_t errors_before = json.error_count();
  json.check_keys(j, pointer, schema::kShader, "shader");
  if (j.contains("ByteCode"))
    json.error(pointer + "/ByteCode",
               "'ByteCode' (bytes in the JSON) is not supported: put the SPIR-V in a file and give it as "
               "'FilePath' with \"SourceLanguage\": \"BYTECODE\"");

  if (auto desc = j.find("Desc"); desc != j.end())
    read_shader_desc(json, *desc, pointer + "/Desc", slot_stage, shader);
  shader.entry_point = json.string(j, "EntryPoint", pointer).value_or("main");
  auto file_path = json.string(j, "FilePath", pointer);
  auto source = json.string(j, "Source", pointer);
  if (!ctx.defaults_mode) {
    if (shader.name.empty()) json.error(pointer, "a shader needs a name ('Desc.Name')");
    if (shader.stage == 0) json.error(pointer, "shader '" + shader.name + "' needs 'Desc.ShaderType'");
    if (file_path && source)
      json.error(pointer, "shader '" + shader.name + "' has both 'FilePath' and 'Source'");
    if (!file_path && !source)
      json.error(pointer, "shader '" + shader.name + "' needs 'FilePath' or 'Source'");
  }
  if (source) shader.source = *source;
  if (auto length = j.find("SourceLength"); length != j.end() && source) {
    // Diligent's SourceLength: the first that many bytes of Source (0: all of it).
    uint32_t bytes = 0;
    json.unsigned_number(j, "SourceLength", pointer, bytes);
    if (bytes > source->size())
      json.error(pointer + "/SourceLength", "'SourceLength' is " + std::to_string(bytes) +
                                                " but 'Source' has only " + std::to_string(source->size()) +
                                                " bytes");
    else if (bytes != 0)
      shader.source.resize(bytes);
  } else if (length != j.end()) {
    uint32_t unused = 0;
    json.unsigned_number(j, "SourceLength", pointer, unused);
  }
  if (file_path && !ctx.defaults_mode) {
    auto found = ctx.resolved_files.find(*file_path);
    if (found == ctx.resolved_files.end())
      found = ctx.resolved_files
                  .emplace(*file_path, resolve_file(*file_path, ctx.base_dir, ctx.options.shader_dirs,
                                                    ctx.options.memory_files))
                  .first;
    shader.file = found->second;
    if (shader.file.empty())
      json.error(pointer + "/FilePath", "shader file '" + *file_path + "' not found next to " + json.file() +
                                            " or in any shader directory (-s)");
  }

  uint32_t language = 0;
  json.enum_field(j, "SourceLanguage", pointer, kSourceLanguages, "source language", language);
  if (language == 1) {
    shader.language = SourceLanguage::hlsl;
  } else if (language == 2 || language == 3) {
    shader.language = SourceLanguage::glsl;
    shader.verbatim = language == 3;
  } else if (language == 0) {
    shader.language = language_from_extension(file_path.value_or(""));
  } else if (language == 8) {
    shader.language = SourceLanguage::spirv;
    if (source && !ctx.defaults_mode)
      json.error(
          pointer + "/Source",
          "shader '" + shader.name + "': BYTECODE is a SPIR-V file: give it as 'FilePath', not 'Source'");
  } else {
    json.error(pointer + "/SourceLanguage",
               "source language '" + j["SourceLanguage"].get<std::string>() +
                   "' is not supported by the Vulkan backend (use GLSL, HLSL, or BYTECODE for SPIR-V)");
  }
  uint32_t compiler = 0;
  json.enum_field(j, "ShaderCompiler", pointer, kShaderCompilers, "shader compiler", compiler);
  if (compiler >= 2 && shader.language != SourceLanguage::spirv)
    json.warning(pointer + "/ShaderCompiler",
                 "statepack compiles with glslang; the compiler choice is ignored");
  read_compile_settings(json, j, pointer, shader);

  if (auto macros = j.find("Macros"); macros != j.end())
    read_macros(json, *macros, pointer + "/Macros", shader);
  // With errors the object is still returned, marked broken, when it has a name: references to it
  // then resolve (one cause, one message) and a different redefinition is still reported.
  if (json.error_count() != errors_before) {
    if (shader.name.empty()) return std::nullopt;
    shader.broken = true;
  }
  return shader;
}

void read_graphics_state(ReadContext& ctx, const Json& j, const std::string& pointer,
                         format::GraphicsState& g, uint32_t& subpass, std::vector<std::string>& semantics) {
  JsonReader& json = ctx.json;
  if (!json.expect_object(j, pointer, "'GraphicsPipeline'")) return;
  json.check_keys(j, pointer, schema::kGraphicsPipelineDesc, "GraphicsPipeline");
  json.enum_field(j, "PrimitiveTopology", pointer, kTopologies, "primitive topology", g.topology);
  if (g.topology > kPatchListTopology) {
    g.patch_control_points = g.topology - kPatchListTopology;
    g.topology = VK_PRIMITIVE_TOPOLOGY_PATCH_LIST;
  }
  json.unsigned_number(j, "SampleMask", pointer, g.sample_mask);
  json.unsigned_number(j, "SubpassIndex", pointer, subpass);
  if (auto it = j.find("InputLayout"); it != j.end())
    read_input_layout(ctx, *it, pointer + "/InputLayout", g, semantics);
  uint32_t viewports = 1, unused = 0;
  json.unsigned_number(j, "NumViewports", pointer, viewports);
  if (viewports != 1) json.error(pointer + "/NumViewports", "only one viewport is supported");
  json.boolean(j, "ReadOnlyDSV", pointer, unused);
  json.unsigned_number(j, "NodeMask", pointer, unused);
  if (auto it = j.find("ShadingRateFlags");
      it != j.end() && !(it->is_string() && *it == "NONE") && !(it->is_array() && it->empty()))
    json.error(pointer + "/ShadingRateFlags", "variable-rate shading is not supported by statepack yet");

  if (auto r = j.find("RasterizerDesc");
      r != j.end() && json.expect_object(*r, pointer + "/RasterizerDesc", "'RasterizerDesc'")) {
    std::string rp = pointer + "/RasterizerDesc";
    json.check_keys(*r, rp, schema::kRasterizerDesc, "RasterizerDesc");
    json.enum_field(*r, "FillMode", rp, kFillModes, "fill mode", g.polygon_mode);
    json.enum_field(*r, "CullMode", rp, kCullModes, "cull mode", g.cull_mode);
    uint32_t ccw = g.front_face == VK_FRONT_FACE_COUNTER_CLOCKWISE, depth_clip = !g.depth_clamp;
    json.boolean(*r, "FrontCounterClockwise", rp, ccw);
    g.front_face = ccw ? VK_FRONT_FACE_COUNTER_CLOCKWISE : VK_FRONT_FACE_CLOCKWISE;
    json.boolean(*r, "DepthClipEnable", rp, depth_clip);
    g.depth_clamp = depth_clip ? 0 : 1;
    json.boolean(*r, "ScissorEnable", rp, unused);  // scissor is always dynamic in Vulkan
    json.boolean(*r, "AntialiasedLineEnable", rp, unused);
    int32_t bias = static_cast<int32_t>(g.depth_bias);
    json.signed_number(*r, "DepthBias", rp, bias);
    g.depth_bias = static_cast<float>(bias);
    json.float_number(*r, "DepthBiasClamp", rp, g.depth_bias_clamp);
    if (g.depth_bias_clamp != 0 && !ctx.defaults_mode)
      json.warning(
          rp + "/DepthBiasClamp",
          "a non-zero 'DepthBiasClamp' needs the depthBiasClamp device feature, which Vulkan does not "
          "guarantee: devices without it refuse the pipeline");
    json.float_number(*r, "SlopeScaledDepthBias", rp, g.depth_bias_slope);
  }
  if (auto d = j.find("DepthStencilDesc");
      d != j.end() && json.expect_object(*d, pointer + "/DepthStencilDesc", "'DepthStencilDesc'")) {
    std::string dp = pointer + "/DepthStencilDesc";
    json.check_keys(*d, dp, schema::kDepthStencilDesc, "DepthStencilDesc");
    json.boolean(*d, "DepthEnable", dp, g.depth_test);
    json.boolean(*d, "DepthWriteEnable", dp, g.depth_write);
    enum_unless_unset(json, *d, "DepthFunc", dp, kComparisonFuncs, "comparison function", g.depth_compare,
                      g.depth_test != 0);
    json.boolean(*d, "StencilEnable", dp, g.stencil_test);
    json.unsigned_number(*d, "StencilReadMask", dp, g.stencil_read_mask);
    json.unsigned_number(*d, "StencilWriteMask", dp, g.stencil_write_mask);
    for (auto [key, op] : {std::pair{"FrontFace", &g.front}, std::pair{"BackFace", &g.back}}) {
      auto f = d->find(key);
      std::string fp = dp + "/" + key;
      if (f == d->end() || !json.expect_object(*f, fp, key)) continue;
      json.check_keys(*f, fp, schema::kStencilOpDesc, "stencil op");
      const bool stencil = g.stencil_test != 0;
      enum_unless_unset(json, *f, "StencilFailOp", fp, kStencilOps, "stencil op", op->fail_op, stencil);
      enum_unless_unset(json, *f, "StencilDepthFailOp", fp, kStencilOps, "stencil op", op->depth_fail_op,
                        stencil);
      enum_unless_unset(json, *f, "StencilPassOp", fp, kStencilOps, "stencil op", op->pass_op, stencil);
      enum_unless_unset(json, *f, "StencilFunc", fp, kComparisonFuncs, "comparison function", op->compare_op,
                        stencil);
    }
  }
  if (auto b = j.find("BlendDesc");
      b != j.end() && json.expect_object(*b, pointer + "/BlendDesc", "'BlendDesc'"))
    read_blend(ctx, *b, pointer + "/BlendDesc", g);

  if (auto f = j.find("RTVFormats"); f != j.end()) {
    // An object keyed by index, as in DRSN (so Defaults can merge per index).
    if (json.expect_object(*f, pointer + "/RTVFormats", "'RTVFormats' (keyed by index, \"0\": ...)")) {
      for (const auto& [key, value] : f->items()) {
        auto index = parse_index(json, key, pointer + "/RTVFormats");
        if (!index) continue;
        if (auto v =
                json.enum_value(value, pointer + "/RTVFormats/" + key, kTextureFormats, "texture format")) {
          g.color_formats[*index] = *v;
          if (is_depth_stencil_format(*v))
            json.error(pointer + "/RTVFormats/" + key,
                       "render target " + key + " has the depth-stencil format " + value.get<std::string>() +
                           "; render targets take color formats (use 'DSVFormat')");
        }
      }
    }
  }
  // NumRenderTargets is inferred from the highest index with a format when absent.
  int highest = -1;
  for (size_t i = 0; i < g.color_formats.size(); ++i)
    if (g.color_formats[i] != VK_FORMAT_UNDEFINED) highest = int(i);
  g.color_count = static_cast<uint32_t>(highest + 1);
  json.unsigned_number(j, "NumRenderTargets", pointer, g.color_count);
  if (g.color_count > format::kMaxColorTargets)
    json.error(pointer + "/NumRenderTargets", "at most 8 render targets");
  json.enum_field(j, "DSVFormat", pointer, kTextureFormats, "texture format", g.depth_stencil_format);
  if (g.depth_stencil_format != VK_FORMAT_UNDEFINED && !is_depth_stencil_format(g.depth_stencil_format))
    json.error(pointer + "/DSVFormat", "'DSVFormat' " + j["DSVFormat"].get<std::string>() +
                                           " is a color format; the depth-stencil target takes D16_UNORM, "
                                           "D24_UNORM_S8_UINT, D32_FLOAT or D32_FLOAT_S8X24_UINT");
  if (auto s = j.find("SmplDesc");
      s != j.end() && json.expect_object(*s, pointer + "/SmplDesc", "'SmplDesc'")) {
    json.check_keys(*s, pointer + "/SmplDesc", schema::kSmplDesc, "SmplDesc");
    json.unsigned_number(*s, "Count", pointer + "/SmplDesc", g.samples);
    json.unsigned_number(*s, "Quality", pointer + "/SmplDesc", unused);
    if (!std::has_single_bit(g.samples) || g.samples > 64)
      json.error(pointer + "/SmplDesc/Count", "the sample count must be 1, 2, 4, 8, 16, 32 or 64");
  }
}

std::optional<format::Sampler> read_sampler(ReadContext& ctx, const Json& j, const std::string& pointer) {
  JsonReader& json = ctx.json;
  if (!json.expect_object(j, pointer, "a sampler description")) return std::nullopt;
  const size_t errors_before = json.error_count();
  json.check_keys(j, pointer, schema::kSamplerDesc, "sampler");
  format::Sampler s;
  uint32_t min = VK_FILTER_LINEAR, mag = VK_FILTER_LINEAR, mip = VK_FILTER_LINEAR, flags = 0, anisotropy = 0;
  json.string(j, "Name", pointer);
  json.enum_field(j, "MinFilter", pointer, kFilterTypes, "filter type", min);
  json.enum_field(j, "MagFilter", pointer, kFilterTypes, "filter type", mag);
  json.enum_field(j, "MipFilter", pointer, kFilterTypes, "filter type", mip);
  json.enum_field(j, "AddressU", pointer, kAddressModes, "address mode", s.address_u);
  json.enum_field(j, "AddressV", pointer, kAddressModes, "address mode", s.address_v);
  json.enum_field(j, "AddressW", pointer, kAddressModes, "address mode", s.address_w);
  json.flags_field(j, "Flags", pointer, kSamplerFlags, "sampler flag", flags);
  json.boolean(j, "UnnormalizedCoords", pointer, s.unnormalized_coordinates);
  json.float_number(j, "MipLODBias", pointer, s.mip_lod_bias);
  json.unsigned_number(j, "MaxAnisotropy", pointer, anisotropy);
  json.enum_field(j, "ComparisonFunc", pointer, kComparisonFuncs, "comparison function", s.compare_op);
  json.float_number(j, "MinLOD", pointer, s.min_lod);
  json.float_number(j, "MaxLOD", pointer, s.max_lod);
  s.min_filter = min & 1;
  s.mag_filter = mag & 1;
  s.mipmap_mode = mip & 1;  // VkSamplerMipmapMode NEAREST = 0, LINEAR = 1
  s.compare_enable = (min & kFilterComparison) ? 1 : 0;
  s.anisotropy_enable = (min & kFilterAnisotropic) ? 1 : 0;
  s.max_anisotropy = s.anisotropy_enable ? static_cast<float>(std::max(1u, anisotropy)) : 1.0f;
  if (auto border = j.find("BorderColor"); border != j.end()) {
    // Vulkan's core border colors: transparent black, opaque black, opaque white.
    std::array<float, 4> c{};
    bool ok = border->is_array() && border->size() == 4;
    for (size_t i = 0; ok && i < 4; ++i) {
      ok = (*border)[i].is_number();
      if (ok) c[i] = (*border)[i].get<float>();
    }
    if (ok && c == std::array<float, 4>{0, 0, 0, 0})
      s.border_color = VK_BORDER_COLOR_FLOAT_TRANSPARENT_BLACK;
    else if (ok && c == std::array<float, 4>{0, 0, 0, 1})
      s.border_color = VK_BORDER_COLOR_FLOAT_OPAQUE_BLACK;
    else if (ok && c == std::array<float, 4>{1, 1, 1, 1})
      s.border_color = VK_BORDER_COLOR_FLOAT_OPAQUE_WHITE;
    else if (!border->is_array() || border->size() != 4 || !ok)
      json.error(pointer + "/BorderColor", "'BorderColor' must be an array of 4 numbers");
    else if (s.address_u == VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_BORDER ||
             s.address_v == VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_BORDER ||
             s.address_w == VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_BORDER)
      // Diligent logs this and uses transparent black; a colour Vulkan's core has not needs an extension.
      json.warning(pointer + "/BorderColor",
                   "Vulkan's core border colors are [0,0,0,0], [0,0,0,1] and [1,1,1,1]; this one becomes "
                   "transparent black [0,0,0,0], as in Diligent");
    // (no address mode is BORDER: Vulkan never reads the colour)
  }
  if (json.error_count() != errors_before) return std::nullopt;
  return s;
}

std::vector<ImmutableSamplerDesc> read_immutable_samplers(ReadContext& ctx, const Json& j,
                                                          const std::string& pointer) {
  JsonReader& json = ctx.json;
  std::vector<ImmutableSamplerDesc> out;
  if (!json.expect_array(j, pointer, "'ImmutableSamplers'")) return out;
  for (size_t i = 0; i < j.size(); ++i) {
    std::string sp = pointer + "/" + std::to_string(i);
    const Json& e = j[i];
    if (!json.expect_object(e, sp, "an immutable sampler")) continue;
    json.check_keys(e, sp, schema::kImmutableSampler, "immutable sampler");
    ImmutableSamplerDesc desc;
    json.stage_flags_field(e, "ShaderStages", sp, desc.stages);
    desc.name = json.string(e, "SamplerOrTextureName", sp).value_or("");
    if (desc.name.empty()) json.error(sp, "an immutable sampler needs 'SamplerOrTextureName'");
    if (auto d = e.find("Desc"); d != e.end()) {
      auto sampler = read_sampler(ctx, *d, sp + "/Desc");
      if (!sampler) continue;
      desc.sampler = *sampler;
    }
    if (!desc.name.empty()) out.push_back(std::move(desc));
  }
  return out;
}

// One entry of a signature's Resources (its object checked by the caller); `inline_values` counts the
// values of every INLINE_CONSTANTS resource of the signature.
SignatureResource read_signature_resource(JsonReader& json, const Json& r, const std::string& rp,
                                          uint32_t& inline_values) {
  SignatureResource res;
  res.name = json.string(r, "Name", rp).value_or("");
  if (res.name.empty()) json.error(rp, "a resource needs a 'Name'");
  const size_t before_stages = json.error_count();
  json.stage_flags_field(r, "ShaderStages", rp, res.stages);
  if (res.stages == 0 && json.error_count() == before_stages)
    json.error(rp, "resource '" + res.name + "' needs 'ShaderStages'");
  json.unsigned_number(r, "ArraySize", rp, res.array_size);
  if (res.array_size == 0) json.error(rp + "/ArraySize", "'ArraySize' must be at least 1");
  uint32_t var_type = 0, flags = 0, type = kUnsupportedValue;
  json.enum_field(r, "VarType", rp, kVariableTypes, "variable type", var_type);
  res.var_type = var_type;
  json.flags_field(r, "Flags", rp, kResourceFlags, "resource flag", flags);
  if (!r.contains("ResourceType")) json.error(rp, "resource '" + res.name + "' needs 'ResourceType'");
  json.enum_field(r, "ResourceType", rp, kResourceTypes, "resource type", type);
  if (flags & kInlineConstants) {
    // Diligent's inline constants: ArraySize 32-bit values, set with vkCmdPushConstants.
    if (type != kConstantBuffer)
      json.error(rp + "/Flags", "resource '" + res.name +
                                    "': INLINE_CONSTANTS applies to CONSTANT_BUFFER "
                                    "resources only");
    else if (flags != kInlineConstants)
      json.error(rp + "/Flags", "resource '" + res.name +
                                    "': INLINE_CONSTANTS cannot be combined with other flags (as in "
                                    "Diligent)");
    else if (res.array_size > kGuaranteedInlineConstants)
      json.error(rp + "/ArraySize", "resource '" + res.name + "': " + std::to_string(res.array_size) +
                                        " inline constants are " + std::to_string(res.array_size * 4) +
                                        " bytes of push constants, more than the 128 bytes Vulkan guarantees "
                                        "(maxPushConstantsSize): at most " +
                                        std::to_string(kGuaranteedInlineConstants));
    res.inline_constants = res.array_size;
    res.array_size = 1;  // its descriptor: ArraySize counts values here, not array elements
    inline_values += res.inline_constants;
  }
  if (flags & kRuntimeArray)
    json.error(rp + "/Flags", "runtime-sized arrays are not supported by statepack yet");
  switch (type) {
    case kConstantBuffer:
      res.descriptor_type = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
      break;
    case kTextureSrv:
      res.descriptor_type = (flags & kCombinedSampler) ? VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER
                                                       : VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE;
      break;
    case kBufferSrv:
      res.descriptor_type = (flags & kFormattedBuffer) ? VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER
                                                       : VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
      break;
    case kTextureUav:
      res.descriptor_type = VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
      break;
    case kBufferUav:
      res.descriptor_type = (flags & kFormattedBuffer) ? VK_DESCRIPTOR_TYPE_STORAGE_TEXEL_BUFFER
                                                       : VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
      break;
    case kSamplerResource:
      res.descriptor_type = VK_DESCRIPTOR_TYPE_SAMPLER;
      break;
    case kInputAttachment:
      res.descriptor_type = VK_DESCRIPTOR_TYPE_INPUT_ATTACHMENT;
      break;
    default:
      break;
  }
  if (res.descriptor_type == VK_DESCRIPTOR_TYPE_INPUT_ATTACHMENT &&
      (res.stages & ~VK_SHADER_STAGE_FRAGMENT_BIT))
    json.error(rp + "/ShaderStages", "input attachment '" + res.name +
                                         "' may only be in the PIXEL stage "
                                         "(VUID-VkDescriptorSetLayoutBinding-descriptorType-01510)");
  return res;
}

std::optional<SignatureDesc> read_signature(ReadContext& ctx, const Json& j, const std::string& pointer) {
  JsonReader& json = ctx.json;
  if (!json.expect_object(j, pointer, "a resource signature")) return std::nullopt;
  const size_t errors_before = json.error_count();
  json.check_keys(j, pointer, schema::kResourceSignature, "resource signature");
  SignatureDesc sig;
  sig.where = json.at(pointer);
  sig.name = json.string(j, "Name", pointer).value_or("");
  if (sig.name.empty() && !ctx.defaults_mode) json.error(pointer, "a resource signature needs a 'Name'");
  json.unsigned_number(j, "BindingIndex", pointer, sig.binding_index);
  if (sig.binding_index >= 8) json.error(pointer + "/BindingIndex", "'BindingIndex' must be 0 to 7");
  uint32_t combined = 0, unused = 0;
  json.boolean(j, "UseCombinedTextureSamplers", pointer, combined);
  if (auto suffix = json.string(j, "CombinedSamplerSuffix", pointer)) sig.combined_sampler_suffix = *suffix;
  if (!combined) sig.combined_sampler_suffix.clear();  // the suffix only matters for combined samplers
  json.unsigned_number(j, "SRBAllocationGranularity", pointer, unused);
  json.unsigned_number(j, "NumResources", pointer, unused);
  json.unsigned_number(j, "NumImmutableSamplers", pointer, unused);
  if (auto samplers = j.find("ImmutableSamplers"); samplers != j.end())
    sig.immutable_samplers = read_immutable_samplers(ctx, *samplers, pointer + "/ImmutableSamplers");

  auto resources = j.find("Resources");
  std::set<std::string> resource_names;
  uint32_t inline_values = 0;  // of every INLINE_CONSTANTS resource
  if (resources != j.end() && json.expect_array(*resources, pointer + "/Resources", "'Resources'")) {
    for (size_t i = 0; i < resources->size(); ++i) {
      std::string rp = pointer + "/Resources/" + std::to_string(i);
      const Json& r = (*resources)[i];
      if (!json.expect_object(r, rp, "a resource")) continue;
      json.check_keys(r, rp, schema::kResource, "resource");
      SignatureResource res = read_signature_resource(json, r, rp, inline_values);
      if (!resource_names.insert(res.name).second)
        json.error(rp + "/Name", "resource '" + res.name + "' is listed twice");
      sig.resources.push_back(std::move(res));
    }
  }
  if (inline_values > 64)  // Diligent's limit per signature (DILIGENT_MAX_INLINE_CONSTANTS)
    json.error(pointer + "/Resources", "resource signature '" + sig.name + "' has " +
                                           std::to_string(inline_values) +
                                           " inline constants in all; Diligent allows 64 per signature");
  // An immutable sampler named like a resource that takes no sampler: with combined samplers and a
  // texture, it becomes the texture's sampler (NAME + CombinedSamplerSuffix, as the shader declares it).
  // Anything else no shader can reach (Diligent gives it a sampler binding of its own that nothing names):
  // a warning, and it is left out.
  for (size_t i = 0, written = 0; i < sig.immutable_samplers.size(); ++written) {
    const ImmutableSamplerDesc& s = sig.immutable_samplers[i];
    const SignatureResource* unreachable = nullptr;
    for (const SignatureResource& r : sig.resources) {
      if (r.name != s.name || r.descriptor_type == VK_DESCRIPTOR_TYPE_SAMPLER ||
          r.descriptor_type == VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER)
        continue;
      if (r.descriptor_type == VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE && !sig.combined_sampler_suffix.empty())
        continue;
      unreachable = &r;
    }
    if (!unreachable) {
      ++i;
      continue;
    }
    json.warning(
        pointer + "/ImmutableSamplers/" + std::to_string(written) + "/SamplerOrTextureName",
        "immutable sampler '" + s.name + "' names resource '" + unreachable->name +
            "', which takes no sampler (a sampler, a combined texture, or a texture of a signature "
            "with 'UseCombinedTextureSamplers' may have one): no shader can use it, so it is left out");
    sig.immutable_samplers.erase(sig.immutable_samplers.begin() + std::ptrdiff_t(i));
  }
  // With errors the object is still returned, marked broken, when it has a name: references to it
  // then resolve (one cause, one message) and a different redefinition is still reported.
  if (json.error_count() != errors_before) {
    if (sig.name.empty()) return std::nullopt;
    sig.broken = true;
  }
  return sig;
}

namespace {

// One entry of 'pAttachments'; std::nullopt when it is not an object (already reported).
std::optional<format::Attachment> read_attachment(ReadContext& ctx, const Json& a, const std::string& ap,
                                                  size_t index) {
  JsonReader& json = ctx.json;
  if (!json.expect_object(a, ap, "an attachment")) return std::nullopt;
  json.check_keys(a, ap, schema::kAttachment, "attachment");
  format::Attachment att;
  att.load_op = VK_ATTACHMENT_LOAD_OP_LOAD;
  att.store_op = VK_ATTACHMENT_STORE_OP_STORE;
  att.stencil_load_op = VK_ATTACHMENT_LOAD_OP_LOAD;
  att.stencil_store_op = VK_ATTACHMENT_STORE_OP_STORE;
  if (!a.contains("Format")) json.error(ap, "an attachment needs a 'Format'");
  json.enum_field(a, "Format", ap, kTextureFormats, "texture format", att.format);
  json.unsigned_number(a, "SampleCount", ap, att.samples);
  if (!std::has_single_bit(att.samples) || att.samples > 64)
    json.error(ap + "/SampleCount", "the sample count must be 1, 2, 4, 8, 16, 32 or 64");
  json.enum_field(a, "LoadOp", ap, kLoadOps, "load op", att.load_op);
  json.enum_field(a, "StoreOp", ap, kStoreOps, "store op", att.store_op);
  json.enum_field(a, "StencilLoadOp", ap, kLoadOps, "load op", att.stencil_load_op);
  json.enum_field(a, "StencilStoreOp", ap, kStoreOps, "store op", att.stencil_store_op);
  json.enum_field(a, "InitialState", ap, kResourceStates, "resource state", att.initial_layout);
  json.enum_field(a, "FinalState", ap, kResourceStates, "resource state", att.final_layout);
  if (att.final_layout == VK_IMAGE_LAYOUT_UNDEFINED)
    json.error(ap, "an attachment needs a 'FinalState' (Vulkan cannot end a render pass in UNDEFINED)");
  // Diligent's defaults (LoadOp LOAD, InitialState UNKNOWN) ask Vulkan to load an image whose layout
  // is UNDEFINED, i.e. whose contents are gone: an error here instead of at pipeline creation.
  const bool stencil_only = att.format == VK_FORMAT_S8_UINT;
  const bool has_stencil = stencil_only || att.format == VK_FORMAT_D24_UNORM_S8_UINT ||
                           att.format == VK_FORMAT_D32_SFLOAT_S8_UINT ||
                           att.format == VK_FORMAT_D16_UNORM_S8_UINT;
  if (!ctx.defaults_mode && att.initial_layout == VK_IMAGE_LAYOUT_UNDEFINED) {
    if (att.load_op == VK_ATTACHMENT_LOAD_OP_LOAD && !stencil_only)
      json.error(ap,
                 "attachment " + std::to_string(index) +
                     ": LoadOp LOAD (the default) needs an 'InitialState': an image in the UNDEFINED layout "
                     "has no contents to load (VUID-VkAttachmentDescription-format-06699); set "
                     "'InitialState' or use LoadOp CLEAR or DISCARD");
    else if (att.stencil_load_op == VK_ATTACHMENT_LOAD_OP_LOAD && has_stencil)
      json.error(ap, "attachment " + std::to_string(index) +
                         ": StencilLoadOp LOAD (the default) needs an 'InitialState' "
                         "(VUID-VkAttachmentDescription-format-06700); set 'InitialState' or use "
                         "StencilLoadOp CLEAR or DISCARD");
  }
  return att;
}

// The states a reference of each use may name (Diligent's render-pass rules, which are Vulkan's: a color
// or resolve attachment in a read-only layout, say, is VUID-VkSubpassDescription-attachment-06913).
struct ReferenceUse {
  const char* what;
  const char* states;
  std::initializer_list<uint32_t> layouts;
};
constexpr ReferenceUse kColorUse{"a render target or resolve attachment",
                                 "RENDER_TARGET or COMMON",
                                 {VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, VK_IMAGE_LAYOUT_GENERAL}};
constexpr ReferenceUse kInputUse{"an input attachment",
                                 "INPUT_ATTACHMENT, DEPTH_READ or COMMON",
                                 {VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
                                  VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL, VK_IMAGE_LAYOUT_GENERAL}};
constexpr ReferenceUse kDepthUse{"a depth-stencil attachment",
                                 "DEPTH_WRITE, DEPTH_READ or COMMON",
                                 {VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL,
                                  VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL, VK_IMAGE_LAYOUT_GENERAL}};

void read_attachment_reference(ReadContext& ctx, const Json& r, const std::string& rp_ptr,
                               size_t attachment_count, const ReferenceUse& use, format::AttachmentRef& out) {
  JsonReader& json = ctx.json;
  if (!json.expect_object(r, rp_ptr, "an attachment reference")) return;
  json.check_keys(r, rp_ptr, schema::kAttachmentReference, "attachment reference");
  json.unsigned_number(r, "AttachmentIndex", rp_ptr, out.attachment);
  json.enum_field(r, "State", rp_ptr, kResourceStates, "resource state", out.layout);
  if (out.attachment != format::kNone && out.attachment >= attachment_count)
    json.error(rp_ptr + "/AttachmentIndex",
               "attachment " + std::to_string(out.attachment) + " does not exist");
  else if (out.attachment != format::kNone && out.layout == VK_IMAGE_LAYOUT_UNDEFINED && !ctx.defaults_mode)
    json.error(rp_ptr,
               "an attachment reference needs a 'State' (a subpass cannot use an attachment in the "
               "UNDEFINED layout: VUID-VkAttachmentReference-layout-03077)");
  else if (out.attachment != format::kNone && !ctx.defaults_mode &&
           std::find(use.layouts.begin(), use.layouts.end(), out.layout) == use.layouts.end())
    json.error(rp_ptr + "/State", std::string("the 'State' of ") + use.what + " must be " + use.states +
                                      ", as in Diligent (Vulkan refuses other layouts for it: "
                                      "VUID-VkSubpassDescription-attachment-06913 and its kin)");
}

// A subpass's list of attachment references under KEY; an entry that is not an object still takes its
// slot, as a default reference.
void read_attachment_references(ReadContext& ctx, const Json& s, const char* key, const std::string& sp,
                                size_t attachment_count, const ReferenceUse& use,
                                std::vector<format::AttachmentRef>& out) {
  auto list = s.find(key);
  if (list == s.end() || !ctx.json.expect_array(*list, sp + "/" + key, key)) return;
  for (size_t i = 0; i < list->size(); ++i)
    read_attachment_reference(ctx, (*list)[i], sp + "/" + key + "/" + std::to_string(i), attachment_count,
                              use, out.emplace_back());
}

void read_preserve_attachments(JsonReader& json, const Json& s, const std::string& sp,
                               size_t attachment_count, format::Subpass& subpass) {
  auto preserve = s.find("pPreserveAttachments");
  if (preserve == s.end() ||
      !json.expect_array(*preserve, sp + "/pPreserveAttachments", "'pPreserveAttachments'"))
    return;
  for (size_t k = 0; k < preserve->size(); ++k) {
    const Json& p = (*preserve)[k];
    if (!p.is_number_unsigned() || p.get<uint64_t>() >= attachment_count)
      json.error(sp + "/pPreserveAttachments/" + std::to_string(k), "not an attachment index");
    else
      subpass.preserve.push_back(p.get<uint32_t>());
  }
}

// One entry of 'pSubpasses'; std::nullopt when it is not an object (already reported).
std::optional<format::Subpass> read_subpass(ReadContext& ctx, const Json& s, const std::string& sp,
                                            size_t attachment_count) {
  JsonReader& json = ctx.json;
  if (!json.expect_object(s, sp, "a subpass")) return std::nullopt;
  json.check_keys(s, sp, schema::kSubpass, "subpass");
  uint32_t unused = 0;
  for (const char* count : {"InputAttachmentCount", "RenderTargetAttachmentCount", "PreserveAttachmentCount"})
    json.unsigned_number(s, count, sp, unused);
  format::Subpass subpass;
  read_attachment_references(ctx, s, "pInputAttachments", sp, attachment_count, kInputUse, subpass.inputs);
  read_attachment_references(ctx, s, "pRenderTargetAttachments", sp, attachment_count, kColorUse,
                             subpass.colors);
  read_attachment_references(ctx, s, "pResolveAttachments", sp, attachment_count, kColorUse,
                             subpass.resolves);
  if (auto d = s.find("pDepthStencilAttachment"); d != s.end())
    read_attachment_reference(ctx, *d, sp + "/pDepthStencilAttachment", attachment_count, kDepthUse,
                              subpass.depth_stencil);
  if (s.contains("pShadingRateAttachment"))
    json.error(sp + "/pShadingRateAttachment", "shading-rate attachments are not supported by statepack yet");
  if (!subpass.resolves.empty() && subpass.resolves.size() != subpass.colors.size())
    json.error(sp + "/pResolveAttachments", "needs one resolve attachment per render target");
  if (subpass.colors.size() > format::kMaxColorTargets)
    json.error(sp + "/pRenderTargetAttachments", "at most 8 render targets");
  read_preserve_attachments(json, s, sp, attachment_count, subpass);
  return subpass;
}

// One entry of 'pDependencies'; std::nullopt when it is not an object (already reported).
std::optional<format::Dependency> read_dependency(ReadContext& ctx, const Json& d, const std::string& dp,
                                                  size_t subpass_count) {
  JsonReader& json = ctx.json;
  if (!json.expect_object(d, dp, "a dependency")) return std::nullopt;
  json.check_keys(d, dp, schema::kDependency, "dependency");
  format::Dependency dep;
  json.unsigned_number(d, "SrcSubpass", dp, dep.src_subpass);
  json.unsigned_number(d, "DstSubpass", dp, dep.dst_subpass);
  json.flags_field(d, "SrcStageMask", dp, kPipelineStages, "pipeline stage", dep.src_stages);
  json.flags_field(d, "DstStageMask", dp, kPipelineStages, "pipeline stage", dep.dst_stages);
  json.flags_field(d, "SrcAccessMask", dp, kAccessFlags, "access flag", dep.src_access);
  json.flags_field(d, "DstAccessMask", dp, kAccessFlags, "access flag", dep.dst_access);
  for (auto [key, mask] :
       {std::pair{"SrcStageMask", dep.src_stages}, std::pair{"DstStageMask", dep.dst_stages}})
    if (mask == 0 && !ctx.defaults_mode)
      json.error(dp, std::string("a dependency needs a '") + key + "' naming at least one pipeline stage (" +
                         (key[0] == 'S' ? "VUID-VkSubpassDependency-srcStageMask-03937"
                                        : "VUID-VkSubpassDependency-dstStageMask-03937") +
                         ")");
  for (auto [key, index] :
       {std::pair{"SrcSubpass", dep.src_subpass}, std::pair{"DstSubpass", dep.dst_subpass}})
    if (index != format::kNone && index >= subpass_count)
      json.error(dp + "/" + key,
                 "subpass " + std::to_string(index) + " does not exist (4294967295 is external)");
  return dep;
}

}  // namespace

std::optional<RenderPassDesc> read_render_pass(ReadContext& ctx, const Json& j, const std::string& pointer) {
  JsonReader& json = ctx.json;
  if (!json.expect_object(j, pointer, "a render pass")) return std::nullopt;
  const size_t errors_before = json.error_count();
  json.check_keys(j, pointer, schema::kRenderPass, "render pass");
  RenderPassDesc desc;
  desc.where = json.at(pointer);
  format::RenderPass& rp = desc.pass;
  rp.name = json.string(j, "Name", pointer).value_or("");
  if (rp.name.empty() && !ctx.defaults_mode) json.error(pointer, "a render pass needs a 'Name'");
  uint32_t unused = 0;
  for (const char* count : {"AttachmentCount", "SubpassCount", "DependencyCount"})
    json.unsigned_number(j, count, pointer, unused);

  if (auto list = j.find("pAttachments");
      list != j.end() && json.expect_array(*list, pointer + "/pAttachments", "'pAttachments'")) {
    for (size_t i = 0; i < list->size(); ++i)
      if (auto att = read_attachment(ctx, (*list)[i], pointer + "/pAttachments/" + std::to_string(i), i))
        rp.attachments.push_back(*att);
  }
  if (auto list = j.find("pSubpasses");
      list != j.end() && json.expect_array(*list, pointer + "/pSubpasses", "'pSubpasses'")) {
    for (size_t i = 0; i < list->size(); ++i)
      if (auto subpass = read_subpass(ctx, (*list)[i], pointer + "/pSubpasses/" + std::to_string(i),
                                      rp.attachments.size()))
        rp.subpasses.push_back(std::move(*subpass));
  }
  if (rp.subpasses.empty() && !ctx.defaults_mode)
    json.error(pointer, "render pass '" + rp.name + "' needs a subpass");
  if (auto list = j.find("pDependencies");
      list != j.end() && json.expect_array(*list, pointer + "/pDependencies", "'pDependencies'")) {
    for (size_t i = 0; i < list->size(); ++i)
      if (auto dep = read_dependency(ctx, (*list)[i], pointer + "/pDependencies/" + std::to_string(i),
                                     rp.subpasses.size()))
        rp.dependencies.push_back(*dep);
  }
  // With errors the object is still returned, marked broken, when it has a name: references to it
  // then resolve (one cause, one message) and a different redefinition is still reported.
  if (json.error_count() != errors_before) {
    if (desc.pass.name.empty()) return std::nullopt;
    desc.broken = true;
  }
  return desc;
}

}  // namespace statepack::packager
