// Reads DRSN JSON strictly: unknown keys and enum strings are errors with a suggestion, every error
// carries file:line:col and the JSON pointer, and reading goes on to report all errors of a file.
#include "notation.hpp"

#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>

#include "enum_tables.hpp"
#include "json_positions.hpp"
#include "suggest.hpp"

namespace statepack::packager {

using nlohmann::json;
namespace fs = std::filesystem;

fs::path resolve_file(const std::string& name, const fs::path& base_dir, const std::vector<fs::path>& dirs) {
  fs::path p(name);
  std::error_code ec;
  if (p.is_absolute()) return fs::is_regular_file(p, ec) ? p : fs::path{};
  if (fs::is_regular_file(base_dir / p, ec)) return (base_dir / p).lexically_normal();
  for (const auto& dir : dirs)
    if (fs::is_regular_file(dir / p, ec)) return (dir / p).lexically_normal();
  return {};
}

std::string display_path(const fs::path& path) {
  std::error_code ec;
  fs::path relative = path.lexically_relative(fs::current_path(ec));
  if (ec || relative.empty() || *relative.begin() == "..") return path.string();
  return relative.string();
}

namespace {

const char* type_name(const json& j) {
  return j.type_name();
}

class FileReader {
 public:
  FileReader(const fs::path& file, std::string display, const std::string& text,
             const NotationOptions& options, Notation& out, Diagnostics& diagnostics)
      : file_(file),
        display_(std::move(display)),
        positions_(text),
        options_(options),
        out_(out),
        diag_(diagnostics) {}

  void read(const json& root) {
    if (!root.is_object())
      return error("", std::string("the top level must be an object, but is ") + type_name(root));
    static const std::vector<std::string> kSections = {
        "Imports", "Defaults", "Shaders", "RenderPasses", "ResourceSignatures", "Pipelines", "Ignore"};
    check_keys(root, "", kSections, "top-level section");
    for (const char* later : {"Imports", "Defaults", "RenderPasses", "ResourceSignatures", "Ignore"})
      if (root.contains(later))
        error("/" + std::string(later),
              "section '" + std::string(later) + "' is not supported by this version of statepack yet");
    if (auto it = root.find("Shaders"); it != root.end()) {
      if (!it->is_array()) {
        error("/Shaders", std::string("'Shaders' must be an array, but is ") + type_name(*it));
      } else {
        for (size_t i = 0; i < it->size(); ++i) {
          std::string ptr = "/Shaders/" + std::to_string(i);
          if (auto shader = read_shader((*it)[i], ptr, 0)) out_.shaders.push_back(std::move(*shader));
        }
      }
    }
    if (auto it = root.find("Pipelines"); it != root.end()) {
      if (!it->is_array()) {
        error("/Pipelines", std::string("'Pipelines' must be an array, but is ") + type_name(*it));
      } else {
        for (size_t i = 0; i < it->size(); ++i) read_pipeline((*it)[i], "/Pipelines/" + std::to_string(i));
      }
    }
  }

 private:
  Location at(const std::string& pointer) const {
    TextPosition p = positions_.find(pointer);
    return {display_, p.line, p.column, pointer};
  }
  void error(const std::string& pointer, std::string message) {
    diag_.error(at(pointer), std::move(message));
  }
  void warning(const std::string& pointer, std::string message) {
    diag_.warning(at(pointer), std::move(message));
  }

  // Reports keys of `object` not in `allowed`, each with a suggestion.
  void check_keys(const json& object, const std::string& pointer, const std::vector<std::string>& allowed,
                  const char* what) {
    for (const auto& [key, value] : object.items()) {
      if (std::find(allowed.begin(), allowed.end(), key) != allowed.end()) continue;
      diag_.error(at_key(pointer + "/" + key),
                  "unknown " + std::string(what) + " key '" + key + "'" + did_you_mean(key, allowed));
    }
  }
  Location at_key(const std::string& pointer) const {
    TextPosition p = positions_.find(pointer + "#key");
    return {display_, p.line, p.column, pointer};
  }

  bool expect_object(const json& j, const std::string& pointer, const char* what) {
    if (j.is_object()) return true;
    error(pointer, std::string(what) + " must be an object, but is " + type_name(j));
    return false;
  }

  std::optional<std::string> string_field(const json& object, const char* key, const std::string& pointer) {
    auto it = object.find(key);
    if (it == object.end()) return std::nullopt;
    if (!it->is_string()) {
      error(pointer + "/" + key, std::string("'") + key + "' must be a string, but is " + type_name(*it));
      return std::nullopt;
    }
    return it->get<std::string>();
  }

  std::optional<uint32_t> enum_value(const json& j, const std::string& pointer, EnumTable table,
                                     const char* enum_name) {
    if (!j.is_string()) {
      error(pointer, std::string(enum_name) + " must be a string, but is " + type_name(j));
      return std::nullopt;
    }
    const auto& s = j.get_ref<const std::string&>();
    for (const auto& [name, value] : table) {
      if (name != s) continue;
      if (value == kUnsupportedValue) {
        error(pointer, std::string(enum_name) + " '" + s + "' is not supported by the Vulkan backend");
        return std::nullopt;
      }
      return value;
    }
    std::vector<std::string> names;
    for (const auto& [name, value] : table) names.emplace_back(name);
    error(pointer, "unknown " + std::string(enum_name) + " '" + s + "'" + did_you_mean(s, names));
    return std::nullopt;
  }

  // Bit-flag enums take one string or an array of strings, ORed together.
  std::optional<uint32_t> flags_value(const json& j, const std::string& pointer, EnumTable table,
                                      const char* enum_name) {
    if (j.is_string()) return enum_value(j, pointer, table, enum_name);
    if (!j.is_array()) {
      error(pointer,
            std::string(enum_name) + " must be a string or an array of strings, but is " + type_name(j));
      return std::nullopt;
    }
    uint32_t bits = 0;
    for (size_t i = 0; i < j.size(); ++i) {
      auto v = enum_value(j[i], pointer + "/" + std::to_string(i), table, enum_name);
      if (!v) return std::nullopt;
      bits |= *v;
    }
    return bits;
  }

  template <class T>
  void number(const json& object, const char* key, const std::string& pointer, T& out) {
    auto it = object.find(key);
    if (it == object.end()) return;
    bool ok = std::is_floating_point_v<T> ? it->is_number() : it->is_number_unsigned();
    if (!ok) {
      error(pointer + "/" + key, std::string("'") + key + "' must be a " +
                                     (std::is_floating_point_v<T> ? "number" : "non-negative integer") +
                                     ", but is " + type_name(*it));
      return;
    }
    out = it->get<T>();
  }

  void boolean(const json& object, const char* key, const std::string& pointer, uint32_t& out) {
    auto it = object.find(key);
    if (it == object.end()) return;
    if (!it->is_boolean())
      return error(pointer + "/" + key,
                   std::string("'") + key + "' must be true or false, but is " + type_name(*it));
    out = it->get<bool>() ? 1 : 0;
  }

  void enum_field(const json& object, const char* key, const std::string& pointer, EnumTable table,
                  const char* enum_name, uint32_t& out) {
    auto it = object.find(key);
    if (it == object.end()) return;
    if (auto v = enum_value(*it, pointer + "/" + key, table, enum_name)) out = *v;
  }

  // --- shaders ------------------------------------------------------------------------------------

  // `slot_stage` is the stage a pipeline slot requires (0 for the Shaders section).
  std::optional<ShaderDesc> read_shader(const json& j, const std::string& pointer, uint32_t slot_stage) {
    ShaderDesc shader;
    shader.where = at(pointer);
    shader.stage = slot_stage;
    if (j.is_string() && slot_stage != 0) {
      shader.name = j.get<std::string>();
      shader.is_reference = true;
      return shader;
    }
    if (!expect_object(j, pointer, slot_stage ? "a shader slot (a name or an object)" : "a shader"))
      return std::nullopt;
    static const std::vector<std::string> kKeys = {"Desc",           "FilePath",
                                                   "Source",         "SourceLength",
                                                   "EntryPoint",     "Macros",
                                                   "SourceLanguage", "ShaderCompiler",
                                                   "HLSLVersion",    "GLSLVersion",
                                                   "GLESSLVersion",  "MSLVersion",
                                                   "CompileFlags",   "LoadConstantBufferReflection",
                                                   "GLSLExtensions", "WebGPUEmulatedArrayIndexSuffix"};
    check_keys(j, pointer, kKeys, "shader");
    const size_t errors_before = diag_.error_count();

    if (auto desc = j.find("Desc"); desc != j.end() && expect_object(*desc, pointer + "/Desc", "'Desc'")) {
      static const std::vector<std::string> kDescKeys = {"Name", "ShaderType", "UseCombinedTextureSamplers",
                                                         "CombinedSamplerSuffix"};
      check_keys(*desc, pointer + "/Desc", kDescKeys, "shader Desc");
      shader.name = string_field(*desc, "Name", pointer + "/Desc").value_or("");
      if (auto type = desc->find("ShaderType"); type != desc->end()) {
        if (auto stage = enum_value(*type, pointer + "/Desc/ShaderType", kShaderTypes, "shader type")) {
          if (slot_stage != 0 && *stage != slot_stage)
            error(pointer + "/Desc/ShaderType", "the shader type does not match the pipeline slot it is in");
          shader.stage = *stage;
        }
      }
    }
    if (shader.name.empty()) error(pointer, "a shader needs a name ('Desc.Name')");
    if (shader.stage == 0) error(pointer, "shader '" + shader.name + "' needs 'Desc.ShaderType'");

    shader.entry_point = string_field(j, "EntryPoint", pointer).value_or("main");
    auto file_path = string_field(j, "FilePath", pointer);
    auto source = string_field(j, "Source", pointer);
    if (file_path && source) error(pointer, "shader '" + shader.name + "' has both 'FilePath' and 'Source'");
    if (!file_path && !source) error(pointer, "shader '" + shader.name + "' needs 'FilePath' or 'Source'");
    if (source) shader.source = *source;
    if (file_path) {
      shader.file_display = *file_path;
      shader.file = resolve_file(*file_path, file_.parent_path(), options_.shader_dirs);
      if (shader.file.empty())
        error(pointer + "/FilePath", "shader file '" + *file_path + "' not found next to " + display_ +
                                         " or in any shader directory (-s)");
    }

    uint32_t language = 0;
    enum_field(j, "SourceLanguage", pointer, kSourceLanguages, "source language", language);
    if (language == 1) {
      shader.language = SourceLanguage::hlsl;
    } else if (language == 2 || language == 3) {
      shader.language = SourceLanguage::glsl;
    } else if (language == 0) {
      shader.language = language_from_extension(file_path.value_or(""));
    } else {
      error(pointer + "/SourceLanguage", "source language '" + j["SourceLanguage"].get<std::string>() +
                                             "' is not supported by the Vulkan backend (use GLSL or HLSL)");
    }
    uint32_t compiler = 0;
    enum_field(j, "ShaderCompiler", pointer, kShaderCompilers, "shader compiler", compiler);
    if (compiler >= 2)
      warning(pointer + "/ShaderCompiler", "statepack compiles with glslang; the compiler choice is ignored");

    if (auto macros = j.find("Macros"); macros != j.end()) {
      if (!macros->is_array()) {
        error(pointer + "/Macros", std::string("'Macros' must be an array, but is ") + type_name(*macros));
      } else {
        for (size_t i = 0; i < macros->size(); ++i) {
          std::string mp = pointer + "/Macros/" + std::to_string(i);
          const json& m = (*macros)[i];
          if (!expect_object(m, mp, "a macro")) continue;
          check_keys(m, mp, {"Name", "Definition"}, "macro");
          auto name = string_field(m, "Name", mp);
          if (!name || name->empty()) {
            error(mp, "a macro needs a 'Name'");
            continue;
          }
          shader.macros.emplace_back(*name, string_field(m, "Definition", mp).value_or(""));
        }
      }
    }
    if (diag_.error_count() != errors_before) return std::nullopt;
    return shader;
  }

  static SourceLanguage language_from_extension(const std::string& path) {
    static const char* kGlsl[] = {".glsl", ".vert", ".frag", ".comp", ".geom", ".tesc", ".tese"};
    std::string ext = fs::path(path).extension().string();
    for (const char* e : kGlsl)
      if (ext == e) return SourceLanguage::glsl;
    return SourceLanguage::hlsl;  // Diligent's DEFAULT means HLSL
  }

  // --- pipelines ----------------------------------------------------------------------------------

  void read_pipeline(const json& j, const std::string& pointer) {
    if (!expect_object(j, pointer, "a pipeline")) return;
    PipelineDesc p;
    p.where = at(pointer);
    auto pso_desc = j.find("PSODesc");
    if (pso_desc == j.end()) return error(pointer, "a pipeline needs 'PSODesc' with a 'Name'");
    if (!expect_object(*pso_desc, pointer + "/PSODesc", "'PSODesc'")) return;
    check_keys(*pso_desc, pointer + "/PSODesc",
               {"Name", "PipelineType", "ResourceLayout", "SRBAllocationGranularity", "ImmediateContextMask"},
               "PSODesc");
    p.name = string_field(*pso_desc, "Name", pointer + "/PSODesc").value_or("");
    if (p.name.empty()) error(pointer + "/PSODesc", "a pipeline needs a name ('PSODesc.Name')");
    p.where.pointer = pointer;

    // The type comes from the shader slots present, as in DRSN; an explicit PipelineType must agree.
    auto has = [&](std::initializer_list<const char*> keys) {
      for (const char* k : keys)
        if (j.contains(k)) return true;
      return false;
    };
    std::optional<uint32_t> inferred;
    if (has({"pAS", "pMS"}))
      inferred = 2;
    else if (has({"pVS", "pPS", "pDS", "pHS", "pGS"}))
      inferred = 0;
    else if (has({"pCS"}))
      inferred = 1;
    else if (has({"pTS"}))
      inferred = 4;
    else if (has({"pGeneralShaders", "pTriangleHitShaders", "pProceduralHitShaders"}))
      inferred = 3;
    std::optional<uint32_t> type = inferred;
    if (auto t = pso_desc->find("PipelineType"); t != pso_desc->end()) {
      auto explicit_type = enum_value(*t, pointer + "/PSODesc/PipelineType", kPipelineTypes, "pipeline type");
      if (explicit_type && inferred && *explicit_type != *inferred)
        return error(pointer + "/PSODesc/PipelineType",
                     "pipeline '" + p.name + "': PipelineType contradicts the shader slots given");
      if (explicit_type) type = explicit_type;
    }
    if (!type) return error(pointer, "pipeline '" + p.name + "' has no shaders, so its type is unknown");
    if (*type >= 2) {
      const char* kinds[] = {"", "", "mesh", "ray-tracing", "tile"};
      return error(pointer, "pipeline '" + p.name + "': " + kinds[*type] +
                                " pipelines are not supported by the Vulkan backend of statepack");
    }
    p.kind = *type == 1 ? format::PipelineKind::compute : format::PipelineKind::graphics;

    if (p.kind == format::PipelineKind::compute) {
      check_keys(j, pointer, {"PSODesc", "Flags", "ppResourceSignatures", "pCS"}, "compute pipeline");
    } else {
      check_keys(
          j, pointer,
          {"PSODesc", "Flags", "ppResourceSignatures", "GraphicsPipeline", "pVS", "pPS", "pDS", "pHS", "pGS"},
          "graphics pipeline");
    }
    if (j.contains("ppResourceSignatures"))
      error(pointer + "/ppResourceSignatures",
            "resource signatures are not supported by this version of statepack yet");

    static const std::pair<const char*, uint32_t> kSlots[] = {
        {"pVS", VK_SHADER_STAGE_VERTEX_BIT},
        {"pHS", VK_SHADER_STAGE_TESSELLATION_CONTROL_BIT},
        {"pDS", VK_SHADER_STAGE_TESSELLATION_EVALUATION_BIT},
        {"pGS", VK_SHADER_STAGE_GEOMETRY_BIT},
        {"pPS", VK_SHADER_STAGE_FRAGMENT_BIT},
        {"pCS", VK_SHADER_STAGE_COMPUTE_BIT},
    };
    for (const auto& [slot, stage] : kSlots) {
      if (auto s = j.find(slot); s != j.end())
        if (auto shader = read_shader(*s, pointer + "/" + slot, stage))
          p.shaders.push_back(std::move(*shader));
    }
    if (p.kind == format::PipelineKind::graphics && !j.contains("pVS"))
      error(pointer, "graphics pipeline '" + p.name + "' needs a vertex shader ('pVS')");

    if (auto layout = pso_desc->find("ResourceLayout"); layout != pso_desc->end())
      read_resource_layout(*layout, pointer + "/PSODesc/ResourceLayout", p);
    if (auto g = j.find("GraphicsPipeline"); g != j.end())
      read_graphics(*g, pointer + "/GraphicsPipeline", p.graphics);

    for (const auto& existing : out_.pipelines)
      if (existing.name == p.name && !p.name.empty())
        return error(pointer, "pipeline '" + p.name + "' is defined twice (first at " +
                                  location_text(existing.where) + ")");
    out_.pipelines.push_back(std::move(p));
  }

  void read_resource_layout(const json& j, const std::string& pointer, PipelineDesc& p) {
    if (!expect_object(j, pointer, "'ResourceLayout'")) return;
    check_keys(j, pointer,
               {"DefaultVariableType", "DefaultVariableMergeStages", "Variables", "ImmutableSamplers"},
               "ResourceLayout");
    uint32_t ignored = 0;
    enum_field(j, "DefaultVariableType", pointer, kVariableTypes, "variable type", ignored);
    if (auto it = j.find("ImmutableSamplers"); it != j.end() && !(it->is_array() && it->empty()))
      error(pointer + "/ImmutableSamplers",
            "immutable samplers are not supported by this version of statepack yet");
    auto vars = j.find("Variables");
    if (vars == j.end()) return;
    if (!vars->is_array()) return error(pointer + "/Variables", "'Variables' must be an array");
    for (size_t i = 0; i < vars->size(); ++i) {
      std::string vp = pointer + "/Variables/" + std::to_string(i);
      const json& v = (*vars)[i];
      if (!expect_object(v, vp, "a variable")) continue;
      check_keys(v, vp, {"Name", "ShaderStages", "Type", "Flags"}, "variable");
      ResourceVariable var;
      var.name = string_field(v, "Name", vp).value_or("");
      if (var.name.empty()) error(vp, "a variable needs a 'Name'");
      if (auto s = v.find("ShaderStages"); s != v.end())
        if (auto bits = flags_value(*s, vp + "/ShaderStages", kShaderStageFlags, "shader stage"))
          var.stages = *bits;
      if (auto t = v.find("Type"); t != v.end())
        if (enum_value(*t, vp + "/Type", kVariableTypes, "variable type")) var.type = t->get<std::string>();
      p.variables.push_back(std::move(var));
    }
  }

  void read_graphics(const json& j, const std::string& pointer, format::GraphicsState& g) {
    if (!expect_object(j, pointer, "'GraphicsPipeline'")) return;
    check_keys(j, pointer,
               {"BlendDesc", "SampleMask", "RasterizerDesc", "DepthStencilDesc", "InputLayout",
                "PrimitiveTopology", "NumViewports", "NumRenderTargets", "SubpassIndex", "ShadingRateFlags",
                "RTVFormats", "DSVFormat", "ReadOnlyDSV", "SmplDesc", "NodeMask", "pRenderPass"},
               "GraphicsPipeline");
    enum_field(j, "PrimitiveTopology", pointer, kTopologies, "primitive topology", g.topology);
    number(j, "SampleMask", pointer, g.sample_mask);
    if (auto it = j.find("InputLayout"); it != j.end()) {
      bool empty = it->is_object() && (!it->contains("LayoutElements") || (*it)["LayoutElements"].empty());
      if (!empty)
        error(pointer + "/InputLayout",
              "vertex input layouts are not supported by this version of statepack yet");
    }
    if (j.contains("pRenderPass"))
      error(pointer + "/pRenderPass",
            "render passes are not supported by this version of statepack yet; "
            "leave pRenderPass out to use dynamic rendering");
    uint32_t viewports = 1;
    number(j, "NumViewports", pointer, viewports);
    if (viewports != 1) error(pointer + "/NumViewports", "only one viewport is supported");

    if (auto r = j.find("RasterizerDesc");
        r != j.end() && expect_object(*r, pointer + "/RasterizerDesc", "'RasterizerDesc'")) {
      std::string rp = pointer + "/RasterizerDesc";
      check_keys(*r, rp,
                 {"FillMode", "CullMode", "FrontCounterClockwise", "DepthClipEnable", "ScissorEnable",
                  "AntialiasedLineEnable", "DepthBias", "DepthBiasClamp", "SlopeScaledDepthBias"},
                 "RasterizerDesc");
      enum_field(*r, "FillMode", rp, kFillModes, "fill mode", g.polygon_mode);
      enum_field(*r, "CullMode", rp, kCullModes, "cull mode", g.cull_mode);
      uint32_t ccw = 0, depth_clip = 1, unused = 0;
      boolean(*r, "FrontCounterClockwise", rp, ccw);
      g.front_face = ccw ? VK_FRONT_FACE_COUNTER_CLOCKWISE : VK_FRONT_FACE_CLOCKWISE;
      boolean(*r, "DepthClipEnable", rp, depth_clip);
      g.depth_clamp = depth_clip ? 0 : 1;
      boolean(*r, "ScissorEnable", rp, unused);  // scissor is always dynamic in Vulkan
      boolean(*r, "AntialiasedLineEnable", rp, unused);
      int32_t bias = 0;
      number(*r, "DepthBias", rp, bias);
      g.depth_bias = static_cast<float>(bias);
      number(*r, "DepthBiasClamp", rp, g.depth_bias_clamp);
      number(*r, "SlopeScaledDepthBias", rp, g.depth_bias_slope);
    }
    if (auto d = j.find("DepthStencilDesc");
        d != j.end() && expect_object(*d, pointer + "/DepthStencilDesc", "'DepthStencilDesc'")) {
      std::string dp = pointer + "/DepthStencilDesc";
      check_keys(*d, dp,
                 {"DepthEnable", "DepthWriteEnable", "DepthFunc", "StencilEnable", "StencilReadMask",
                  "StencilWriteMask", "FrontFace", "BackFace"},
                 "DepthStencilDesc");
      boolean(*d, "DepthEnable", dp, g.depth_test);
      boolean(*d, "DepthWriteEnable", dp, g.depth_write);
      enum_field(*d, "DepthFunc", dp, kComparisonFuncs, "comparison function", g.depth_compare);
      boolean(*d, "StencilEnable", dp, g.stencil_test);
      number(*d, "StencilReadMask", dp, g.stencil_read_mask);
      number(*d, "StencilWriteMask", dp, g.stencil_write_mask);
      for (auto [key, op] : {std::pair{"FrontFace", &g.front}, std::pair{"BackFace", &g.back}}) {
        auto f = d->find(key);
        if (f == d->end() || !expect_object(*f, dp + "/" + key, key)) continue;
        std::string fp = dp + "/" + key;
        check_keys(*f, fp, {"StencilFailOp", "StencilDepthFailOp", "StencilPassOp", "StencilFunc"},
                   "stencil op");
        enum_field(*f, "StencilFailOp", fp, kStencilOps, "stencil op", op->fail_op);
        enum_field(*f, "StencilDepthFailOp", fp, kStencilOps, "stencil op", op->depth_fail_op);
        enum_field(*f, "StencilPassOp", fp, kStencilOps, "stencil op", op->pass_op);
        enum_field(*f, "StencilFunc", fp, kComparisonFuncs, "comparison function", op->compare_op);
      }
    }
    if (auto b = j.find("BlendDesc");
        b != j.end() && expect_object(*b, pointer + "/BlendDesc", "'BlendDesc'"))
      read_blend(*b, pointer + "/BlendDesc", g);

    int highest_format = -1;
    if (auto f = j.find("RTVFormats"); f != j.end()) {
      // An object keyed by index, as in DRSN (so Defaults can merge per index).
      if (!f->is_object()) {
        error(pointer + "/RTVFormats",
              std::string("'RTVFormats' must be an object keyed by index (\"0\": ...), but is ") +
                  type_name(*f));
      } else {
        for (const auto& [key, value] : f->items()) {
          auto index = parse_index(key, pointer + "/RTVFormats");
          if (!index) continue;
          if (auto v = enum_value(value, pointer + "/RTVFormats/" + key, kTextureFormats, "texture format")) {
            g.color_formats[*index] = *v;
            if (*v != VK_FORMAT_UNDEFINED) highest_format = std::max(highest_format, int(*index));
          }
        }
      }
    }
    g.color_count = static_cast<uint32_t>(highest_format + 1);  // NumRenderTargets inferred when absent
    number(j, "NumRenderTargets", pointer, g.color_count);
    if (g.color_count > format::kMaxColorTargets)
      error(pointer + "/NumRenderTargets", "at most 8 render targets");
    enum_field(j, "DSVFormat", pointer, kTextureFormats, "texture format", g.depth_stencil_format);
    if (auto s = j.find("SmplDesc"); s != j.end() && expect_object(*s, pointer + "/SmplDesc", "'SmplDesc'")) {
      check_keys(*s, pointer + "/SmplDesc", {"Count", "Quality"}, "SmplDesc");
      number(*s, "Count", pointer + "/SmplDesc", g.samples);
      if (!std::has_single_bit(g.samples) || g.samples > 64)
        error(pointer + "/SmplDesc/Count", "the sample count must be 1, 2, 4, 8, 16, 32 or 64");
    }
  }

  std::optional<uint32_t> parse_index(const std::string& key, const std::string& pointer) {
    if (key.size() == 1 && key[0] >= '0' && key[0] < '0' + int(format::kMaxColorTargets))
      return static_cast<uint32_t>(key[0] - '0');
    diag_.error(at_key(pointer + "/" + key), "render-target index '" + key + "' must be \"0\" to \"7\"");
    return std::nullopt;
  }

  void read_blend(const json& b, const std::string& pointer, format::GraphicsState& g) {
    check_keys(b, pointer, {"AlphaToCoverageEnable", "IndependentBlendEnable", "RenderTargets"}, "BlendDesc");
    boolean(b, "AlphaToCoverageEnable", pointer, g.alpha_to_coverage);
    uint32_t independent = 0;
    boolean(b, "IndependentBlendEnable", pointer, independent);
    auto rts = b.find("RenderTargets");
    if (rts == b.end()) return;
    if (!rts->is_object())
      return error(pointer + "/RenderTargets", "'RenderTargets' must be an object keyed by index");
    for (const auto& [key, rt] : rts->items()) {
      auto index = parse_index(key, pointer + "/RenderTargets");
      std::string rp = pointer + "/RenderTargets/" + key;
      if (!index || !expect_object(rt, rp, "a render-target blend description")) continue;
      check_keys(rt, rp,
                 {"BlendEnable", "LogicOperationEnable", "SrcBlend", "DestBlend", "BlendOp", "SrcBlendAlpha",
                  "DestBlendAlpha", "BlendOpAlpha", "LogicOp", "RenderTargetWriteMask"},
                 "render-target blend");
      format::BlendAttachment& a = g.blend[*index];
      boolean(rt, "BlendEnable", rp, a.enable);
      uint32_t logic = 0;
      boolean(rt, "LogicOperationEnable", rp, logic);
      if (logic)
        error(rp + "/LogicOperationEnable",
              "logic operations are not supported by this version of statepack yet");
      enum_field(rt, "SrcBlend", rp, kBlendFactors, "blend factor", a.src_color);
      enum_field(rt, "DestBlend", rp, kBlendFactors, "blend factor", a.dst_color);
      enum_field(rt, "BlendOp", rp, kBlendOps, "blend operation", a.color_op);
      enum_field(rt, "SrcBlendAlpha", rp, kBlendFactors, "blend factor", a.src_alpha);
      enum_field(rt, "DestBlendAlpha", rp, kBlendFactors, "blend factor", a.dst_alpha);
      enum_field(rt, "BlendOpAlpha", rp, kBlendOps, "blend operation", a.alpha_op);
      if (auto m = rt.find("RenderTargetWriteMask"); m != rt.end())
        if (auto bits = flags_value(*m, rp + "/RenderTargetWriteMask", kColorMasks, "color mask"))
          a.write_mask = *bits;
    }
    // Without independent blending every target uses target 0's description (D3D semantics).
    if (!independent)
      for (size_t i = 1; i < g.blend.size(); ++i) g.blend[i] = g.blend[0];
  }

  fs::path file_;
  std::string display_;
  JsonPositions positions_;
  const NotationOptions& options_;
  Notation& out_;
  Diagnostics& diag_;
};

}  // namespace

void read_notation(const fs::path& input, const NotationOptions& options, Notation& notation,
                   Diagnostics& diag) {
  fs::path path = resolve_file(input.string(), fs::current_path(), options.render_state_dirs);
  if (path.empty())
    return diag.error({input.string()}, "cannot find render-state file (also searched the -r directories)");
  std::ifstream stream(path, std::ios::binary);
  std::stringstream buffer;
  buffer << stream.rdbuf();
  if (!stream) return diag.error({input.string()}, "cannot read render-state file");
  notation.files_read.push_back(fs::absolute(path).lexically_normal());
  std::string text = buffer.str();
  json root;
  try {
    root = json::parse(text);
  } catch (const json::parse_error& e) {
    // nlohmann's message has "at line L, column C"; map the byte offset to line and column ourselves.
    int line = 1, column = 1;
    for (size_t i = 0; i + 1 < e.byte && i < text.size(); ++i) {
      if (text[i] == '\n')
        ++line, column = 1;
      else
        ++column;
    }
    std::string what = e.what();
    auto colon = what.find("syntax error");
    diag.error({input.string(), line, column, ""},
               "invalid JSON: " + (colon != std::string::npos ? what.substr(colon) : what));
    return;
  }
  // Messages name the file as the user wrote it when it was found as written.
  std::string display = input.is_absolute() ? input.string() : display_path(path);
  FileReader(path, display, text, options, notation, diag).read(root);
}

void resolve_references(Notation& notation, Diagnostics& diag) {
  for (auto& pipeline : notation.pipelines) {
    for (auto& shader : pipeline.shaders) {
      if (!shader.is_reference) continue;
      const ShaderDesc* found = nullptr;
      for (const auto& s : notation.shaders)
        if (s.name == shader.name) found = &s;
      if (!found) {
        std::vector<std::string> names;
        for (const auto& s : notation.shaders) names.push_back(s.name);
        diag.error(shader.where, "pipeline '" + pipeline.name + "' refers to unknown shader '" + shader.name +
                                     "'" + did_you_mean(shader.name, names));
        continue;
      }
      if (found->stage != shader.stage) {
        diag.error(shader.where, "pipeline '" + pipeline.name + "': shader '" + shader.name +
                                     "' has another stage than the slot it is used in");
        continue;
      }
      Location where = shader.where;
      shader = *found;
      shader.where = where;
    }
  }
}

}  // namespace statepack::packager
