// Reads notation files: imports (relative to the importing file, then -r dirs, cycles reported with
// their chain), file-local Defaults merged key by key, named objects with identical redefinition
// allowed, and pipelines whose inline shaders, signatures and render passes are registered by name.
#include "notation.hpp"

#include <algorithm>
#include <array>
#include <optional>
#include <unordered_map>

#include "json_document.hpp"
#include "json_reader.hpp"
#include "notation_objects.hpp"
#include "notation_schema.hpp"
#include "support/suggest.hpp"

namespace statepack::packager {
namespace fs = std::filesystem;

fs::path resolve_file(const std::string& name, const fs::path& base_dir, const std::vector<fs::path>& dirs,
                      const std::map<std::string, std::string>* memory_files) {
  fs::path p(name);
  if (name.empty() || name.find('\0') != std::string::npos) return {};
  std::vector<fs::path> candidates;
  if (p.is_absolute()) {
    candidates.push_back(p.lexically_normal());
  } else {
    candidates.push_back((base_dir / p).lexically_normal());
    std::error_code ec;
    for (const auto& dir : dirs)
      candidates.push_back(memory_files ? (dir / p).lexically_normal()
                                        : fs::absolute(dir / p, ec).lexically_normal());
  }
  if (memory_files) {
    for (const auto& c : candidates)
      if (memory_files->count(c.string())) return c;
    return {};
  }
  std::error_code ec;
  for (const auto& c : candidates)
    if (fs::is_regular_file(c, ec)) return c;
  for (const auto& c : candidates)
    if (fs::exists(c, ec)) return c;
  return {};
}

std::string_view SourceTexts::add(const std::string& file, std::string text) {
  auto source = std::make_unique<Source>();
  source->text = std::move(text);
  std::string_view view = source->text;
  by_file_[file] = std::move(source);
  return view;
}

std::vector<std::pair<std::string_view, std::string_view>> SourceTexts::all() const {
  std::vector<std::pair<std::string_view, std::string_view>> out;
  for (const auto& [file, source] : by_file_) out.emplace_back(file, source->text);
  std::sort(out.begin(), out.end());
  return out;
}

Location SourceTexts::at(const Location& object, const std::string& pointer) const {
  Location where{object.file, object.line, object.column, pointer};
  auto it = by_file_.find(object.file);
  if (it == by_file_.end()) return where;
  Source& source = *it->second;
  if (!source.positions) source.positions = std::make_unique<JsonPositions>(strip_utf8_bom(source.text));
  TextPosition p = source.positions->find(where.pointer);
  if (p.line > 0) where.line = p.line, where.column = p.column;
  return where;
}

const fs::path& working_directory() {
  static const fs::path cwd = [] {
    std::error_code ec;
    fs::path here = fs::current_path(ec);
    return ec ? fs::path() : here;
  }();
  return cwd;
}

std::string display_path(const fs::path& path) {
  const fs::path& cwd = working_directory();
  if (cwd.empty()) return path.string();
  fs::path relative = path.lexically_relative(cwd);
  if (relative.empty() || *relative.begin() == "..") return path.string();
  return relative.string();
}

namespace {

// DRSN's merge: objects merge key by key, recursively; anything else (arrays included) replaces.
Json merge(const Json& base, const Json& over) {
  if (!base.is_object() || !over.is_object()) return over;
  Json out = base;
  for (const auto& [key, value] : over.items()) out[key] = out.contains(key) ? merge(out[key], value) : value;
  return out;
}

struct Defaults {
  Json shader = Json::object(), render_pass = Json::object(), signature = Json::object(),
       pipeline = Json::object();
};

class FileReader {
 public:
  FileReader(const fs::path& file, const std::string& display, std::string_view text,
             const NotationOptions& options, Notation& out, Diagnostics& diagnostics)
      : json_(display, text, diagnostics),
        ctx_{json_, file.parent_path(), options},
        out_(out),
        options_(options) {}

  // The file's top level checked, and its Imports array if it has a valid one. Imports are read first,
  // fully, with their own (empty) defaults (DRSN's defaults are file-local), then finish() reads the rest.
  const Json* begin(const Json& root) {
    if (!root.is_object()) {
      json_.error("", std::string("the top level must be an object, but is ") + root.type_name());
      return nullptr;
    }
    json_.check_keys(root, "", schema::kTopLevel, "top-level section");
    auto it = root.find("Imports");
    if (it == root.end() || !json_.expect_array(*it, "/Imports", "'Imports'")) return nullptr;
    return &*it;
  }

  // Import `i` of `imports`: the file it names, or nothing (the error reported).
  std::optional<fs::path> import_path(const Json& imports, size_t i) {
    std::string pointer = "/Imports/" + std::to_string(i);
    if (!imports[i].is_string()) {
      json_.error(pointer, std::string("an import must be a file name, but is ") + imports[i].type_name());
      return std::nullopt;
    }
    std::string name = imports[i].get<std::string>();
    fs::path path = resolve_file(name, ctx_.base_dir, options_.render_state_dirs, options_.memory_files);
    if (path.empty()) {
      json_.error(pointer, "imported file '" + name + "' not found next to " + json_.file() +
                               " or in any render-state directory (-r)");
      out_.failed_imports.push_back(name);
      return std::nullopt;
    }
    out_.lookups.push_back({false, name, ctx_.base_dir, path});
    return path;
  }
  Location import_location(size_t i) { return json_.at("/Imports/" + std::to_string(i)); }

  void finish(const Json& root) {
    if (!root.is_object()) return;
    if (auto it = root.find("Ignore"); it != root.end()) read_ignore(*it);
    if (auto it = root.find("Defaults"); it != root.end()) read_defaults(*it);
    for_each_item(root, "Shaders", [&](const Json& j, const std::string& p) { shader_object(j, p, 0); });
    for_each_item(root, "RenderPasses",
                  [&](const Json& j, const std::string& p) { render_pass_object(j, p); });
    for_each_item(root, "ResourceSignatures",
                  [&](const Json& j, const std::string& p) { signature_object(j, p); });
    for_each_item(root, "Pipelines", [&](const Json& j, const std::string& p) { pipeline(j, p); });
    for (const auto& [name, found] : ctx_.resolved_files)
      out_.lookups.push_back({true, name, ctx_.base_dir, found});
  }

 private:
  template <class F>
  void for_each_item(const Json& root, const char* section, F&& f) {
    auto it = root.find(section);
    std::string pointer = std::string("/") + section;
    if (it == root.end() || !json_.expect_array(*it, pointer, (std::string("'") + section + "'").c_str()))
      return;
    if (std::string_view(section) == "Pipelines") out_.pipelines.reserve(out_.pipelines.size() + it->size());
    for (size_t i = 0; i < it->size() && !json_.diagnostics().full(); ++i)
      f((*it)[i], pointer + "/" + std::to_string(i));
  }

  void read_ignore(const Json& ignore) {
    if (!json_.expect_object(ignore, "/Ignore", "'Ignore'")) return;
    json_.check_keys(ignore, "/Ignore", schema::kIgnore, "Ignore");
    auto names = ignore.find("Signatures");
    if (names == ignore.end() || !json_.expect_array(*names, "/Ignore/Signatures", "'Signatures'")) return;
    for (size_t i = 0; i < names->size(); ++i) {
      if ((*names)[i].is_string())
        out_.ignored_signatures.insert((*names)[i].get<std::string>());
      else
        json_.error("/Ignore/Signatures/" + std::to_string(i), "a signature name must be a string");
    }
  }

  // Each default block is checked on its own (so its errors are reported once, at its place);
  // a block with errors is not applied.
  void read_defaults(const Json& defaults) {
    if (!json_.expect_object(defaults, "/Defaults", "'Defaults'")) return;
    json_.check_keys(defaults, "/Defaults", schema::kDefaults, "Defaults");
    ReadContext lenient = ctx_;
    lenient.defaults_mode = true;
    auto checked = [&](const char* key, auto&& check) -> Json {
      auto it = defaults.find(key);
      if (it == defaults.end()) return Json::object();
      std::string pointer = std::string("/Defaults/") + key;
      if (!json_.expect_object(*it, pointer, key)) return Json::object();
      size_t before = json_.error_count();
      check(*it, pointer);
      return json_.error_count() == before ? *it : Json::object();
    };
    defaults_.shader =
        checked("Shader", [&](const Json& j, const std::string& p) { read_shader(lenient, j, p, 0); });
    defaults_.render_pass =
        checked("RenderPass", [&](const Json& j, const std::string& p) { read_render_pass(lenient, j, p); });
    defaults_.signature = checked(
        "ResourceSignature", [&](const Json& j, const std::string& p) { read_signature(lenient, j, p); });
    defaults_.pipeline = checked("Pipeline", [&](const Json& j, const std::string& p) {
      json_.check_keys(j, p, schema::kDefaultPipeline, "default pipeline");
      if (auto d = j.find("PSODesc"); d != j.end() && json_.expect_object(*d, p + "/PSODesc", "'PSODesc'")) {
        json_.check_keys(*d, p + "/PSODesc", schema::kDefaultPSODesc, "default PSODesc");
        uint32_t type = 0;
        json_.enum_field(*d, "PipelineType", p + "/PSODesc", kPipelineTypes, "pipeline type", type);
        if (d->contains("PipelineType"))
          json_.warning(
              p + "/PSODesc/PipelineType",
              "a default 'PipelineType' is ignored, as in Diligent: each pipeline's type comes from "
              "its shader slots (or its own PSODesc.PipelineType)");
        json_.string(*d, "Name", p + "/PSODesc");
        PipelineDesc scratch;
        if (auto layout = d->find("ResourceLayout"); layout != d->end())
          resource_layout(*layout, p + "/PSODesc/ResourceLayout", scratch);
      }
      uint32_t flags = 0;
      json_.flags_field(j, "Flags", p, kPipelineFlags, "pipeline flag", flags);
      if (auto g = j.find("GraphicsPipeline"); g != j.end()) {
        format::GraphicsState scratch;
        uint32_t subpass = 0;
        std::vector<std::string> semantics;
        read_graphics_state(lenient, *g, p + "/GraphicsPipeline", scratch, subpass, semantics);
        if (g->contains("pRenderPass"))
          json_.warning(p + "/GraphicsPipeline/pRenderPass",
                        "a default render pass is ignored, as in Diligent: name it in each pipeline");
      }
      if (auto s = j.find("ppResourceSignatures"); s != j.end())
        signature_list(*s, p + "/ppResourceSignatures");
    });
    // What Diligent's parser reads in a default pipeline and then ignores (warned about above).
    if (auto d = defaults_.pipeline.find("PSODesc"); d != defaults_.pipeline.end() && d->is_object())
      d->erase("PipelineType");
    if (auto g = defaults_.pipeline.find("GraphicsPipeline"); g != defaults_.pipeline.end() && g->is_object())
      g->erase("pRenderPass");
  }

  // --- named objects -------------------------------------------------------------------------------

  // Names are looked up in an index, not by scanning the list: thousands of objects stay linear.
  template <class T, class NameOf>
  void add_named(std::vector<T>& list, std::unordered_map<std::string, size_t>& index, T object,
                 NameOf&& name_of, const char* kind) {
    auto [it, inserted] = index.try_emplace(name_of(object), list.size());
    if (!inserted) {
      const T& existing = list[it->second];
      if (!existing.same_as(object))
        json_.diagnostics().error(object.where, std::string(kind) + " '" + name_of(object) +
                                                    "' is defined again differently (first at " +
                                                    location_text(existing.where) + ")");
      return;  // an identical redefinition is allowed, as in DRSN
    }
    list.push_back(std::move(object));
  }

  std::optional<ShaderDesc> shader_object(const Json& j, const std::string& pointer, uint32_t slot_stage) {
    if (!j.is_object()) return read_shader(ctx_, j, pointer, slot_stage);  // reports the type error
    auto shader = defaults_.shader.empty()
                      ? read_shader(ctx_, j, pointer, slot_stage)
                      : read_shader(ctx_, merge(defaults_.shader, j), pointer, slot_stage);
    if (!shader) return shader;
    // One name, one shader, whether it is defined in the Shaders section or inline in a pipeline.
    auto name_of = [](const ShaderDesc& s) { return s.name; };
    const auto& other_index = slot_stage == 0 ? out_.inline_shader_index : out_.shader_index;
    const auto& others = slot_stage == 0 ? out_.inline_shaders : out_.shaders;
    if (auto it = other_index.find(shader->name); it != other_index.end()) {
      if (!others[it->second].same_as(*shader))
        json_.diagnostics().error(shader->where, "shader '" + shader->name +
                                                     "' is defined again differently (first at " +
                                                     location_text(others[it->second].where) + ")");
      if (slot_stage != 0) return shader;  // the Shaders-section definition stands for it
    }
    if (slot_stage == 0)
      add_named(out_.shaders, out_.shader_index, *shader, name_of, "shader");
    else
      add_named(out_.inline_shaders, out_.inline_shader_index, *shader, name_of, "shader");
    return shader;
  }

  std::optional<std::string> render_pass_object(const Json& j, const std::string& pointer) {
    if (j.is_string()) return j.get<std::string>();
    if (!j.is_object()) {
      json_.error(pointer, std::string("a render pass must be a name or an object, but is ") + j.type_name());
      return std::nullopt;
    }
    auto pass = read_render_pass(ctx_, merge(defaults_.render_pass, j), pointer);
    if (!pass) return std::nullopt;
    std::string name = pass->pass.name;
    add_named(
        out_.render_passes, out_.render_pass_index, std::move(*pass),
        [](const RenderPassDesc& r) { return r.pass.name; }, "render pass");
    return name;
  }

  std::optional<std::string> signature_object(const Json& j, const std::string& pointer) {
    if (j.is_string()) return j.get<std::string>();
    if (!j.is_object()) {
      json_.error(pointer,
                  std::string("a resource signature must be a name or an object, but is ") + j.type_name());
      return std::nullopt;
    }
    auto sig = read_signature(ctx_, merge(defaults_.signature, j), pointer);
    if (!sig) return std::nullopt;
    std::string name = sig->name;
    add_named(
        out_.signatures, out_.signature_index, std::move(*sig), [](const SignatureDesc& s) { return s.name; },
        "resource signature");
    return name;
  }

  std::vector<std::string> signature_list(const Json& j, const std::string& pointer) {
    std::vector<std::string> names;
    if (!json_.expect_array(j, pointer, "'ppResourceSignatures'")) return names;
    for (size_t i = 0; i < j.size(); ++i)
      if (auto name = signature_object(j[i], pointer + "/" + std::to_string(i))) names.push_back(*name);
    return names;
  }

  // --- pipelines -----------------------------------------------------------------------------------

  void resource_layout(const Json& j, const std::string& pointer, PipelineDesc& p) {
    if (!json_.expect_object(j, pointer, "'ResourceLayout'")) return;
    json_.check_keys(j, pointer, schema::kResourceLayout, "ResourceLayout");
    uint32_t unused = 0;
    json_.enum_field(j, "DefaultVariableType", pointer, kVariableTypes, "variable type", unused);
    json_.flags_field(j, "DefaultVariableMergeStages", pointer, kShaderStageFlags, "shader stage", unused);
    json_.unsigned_number(j, "NumVariables", pointer, unused);
    json_.unsigned_number(j, "NumImmutableSamplers", pointer, unused);
    if (auto it = j.find("ImmutableSamplers"); it != j.end()) {
      p.immutable_samplers = read_immutable_samplers(ctx_, *it, pointer + "/ImmutableSamplers");
      for (size_t i = 0; i < p.immutable_samplers.size(); ++i)
        p.immutable_sampler_pointers.push_back(pointer + "/ImmutableSamplers/" + std::to_string(i));
    }
    auto vars = j.find("Variables");
    if (vars == j.end() || !json_.expect_array(*vars, pointer + "/Variables", "'Variables'")) return;
    for (size_t i = 0; i < vars->size(); ++i) {
      std::string vp = pointer + "/Variables/" + std::to_string(i);
      const Json& v = (*vars)[i];
      if (!json_.expect_object(v, vp, "a variable")) continue;
      json_.check_keys(v, vp, schema::kVariable, "variable");
      ResourceVariable var;
      var.pointer = vp;
      var.name = json_.string(v, "Name", vp).value_or("");
      if (var.name.empty()) json_.error(vp, "a variable needs a 'Name'");
      json_.stage_flags_field(v, "ShaderStages", vp, var.stages);
      json_.enum_field(v, "Type", vp, kVariableTypes, "variable type", unused);
      uint32_t flags = 0;
      json_.flags_field(v, "Flags", vp, kVariableFlags, "variable flag", flags);
      var.inline_constants = (flags & kVariableInlineConstants) != 0;
      if (var.inline_constants && flags != kVariableInlineConstants)
        json_.error(vp + "/Flags",
                    "variable '" + var.name +
                        "': INLINE_CONSTANTS cannot be combined with other flags (as in Diligent)");
      p.variables.push_back(std::move(var));
    }
  }

  // pSpecializationConstants: [{Name, ShaderStages, Value, Size}] (Diligent's field; Value is statepack's
  // typed spelling of pData, its type decided by the shader's declaration).
  void specialization_constants(const Json& j, const std::string& pointer, PipelineDesc& p) {
    uint32_t unused = 0;
    json_.unsigned_number(j, "NumSpecializationConstants", pointer, unused);
    auto list = j.find("pSpecializationConstants");
    const std::string lp = pointer + "/pSpecializationConstants";
    if (list == j.end() || !json_.expect_array(*list, lp, "'pSpecializationConstants'")) return;
    std::set<std::string> seen;
    for (size_t i = 0; i < list->size(); ++i) {
      const std::string sp = lp + "/" + std::to_string(i);
      const Json& e = (*list)[i];
      if (!json_.expect_object(e, sp, "a specialization constant")) continue;
      json_.check_keys(e, sp, schema::kSpecializationConstant, "specialization constant");
      SpecConstantDesc k;
      k.where = json_.at(sp);
      k.name = json_.string(e, "Name", sp).value_or("");
      if (k.name.empty()) json_.error(sp, "a specialization constant needs a 'Name'");
      json_.stage_flags_field(e, "ShaderStages", sp, k.stages);
      if (e.contains("pData"))
        json_.error(sp + "/pData",
                    "'pData' (raw bytes) is not supported: give the value as 'Value' (a number or "
                    "true/false), typed by the shader's declaration");
      if (e.contains("Size")) {
        uint32_t size = 0;
        json_.unsigned_number(e, "Size", sp, size);
        k.size = size;
      }
      auto value = e.find("Value");
      if (value == e.end()) {
        json_.error(sp, "specialization constant '" + k.name + "' needs a 'Value'");
        continue;
      }
      k.value.text = describe_value(*value);
      if (value->is_boolean()) {
        k.value.kind = ScalarValue::Kind::boolean, k.value.boolean = value->get<bool>();
      } else if (value->is_number_unsigned()) {
        k.value.kind = ScalarValue::Kind::unsigned_integer, k.value.unsigned_integer = value->get<uint64_t>();
      } else if (value->is_number_integer()) {
        k.value.kind = ScalarValue::Kind::signed_integer, k.value.signed_integer = value->get<int64_t>();
      } else if (value->is_number_float()) {
        k.value.kind = ScalarValue::Kind::floating, k.value.floating = value->get<double>();
      } else {
        json_.error(sp + "/Value",
                    "'Value' must be a number or true/false, but is " + describe_value(*value));
        continue;
      }
      if (!k.name.empty() && !seen.insert(k.name).second)
        json_.error(sp + "/Name", "specialization constant '" + k.name + "' is listed twice");
      p.constants.push_back(std::move(k));
    }
  }

  // Whether the pipeline's PrimitiveTopology is written as a patch list, known or not (an unknown
  // count is its own error; no second one about tessellation).
  static bool names_patch_list(const Json& pipeline) {
    auto g = pipeline.find("GraphicsPipeline");
    if (g == pipeline.end() || !g->is_object()) return false;
    auto t = g->find("PrimitiveTopology");
    return t != g->end() && t->is_string() && t->get<std::string>().ends_with("_CONTROL_POINT_PATCHLIST");
  }

  void pipeline(const Json& raw, const std::string& pointer) {
    if (!json_.expect_object(raw, pointer, "a pipeline")) return;
    PipelineDesc p;
    p.where = json_.at(pointer);
    // The type comes from the shader slots present, as in DRSN; an explicit PipelineType must agree.
    auto has = [&](std::initializer_list<const char*> keys) {
      for (const char* k : keys)
        if (raw.contains(k)) return true;
      return false;
    };
    std::optional<uint32_t> type;
    if (has({"pAS", "pMS"}))
      type = 2;
    else if (has({"pVS", "pPS", "pDS", "pHS", "pGS"}))
      type = 0;
    else if (has({"pCS"}))
      type = 1;
    else if (has({"pTS"}))
      type = 4;
    else if (has({"pGeneralShaders", "pTriangleHitShaders", "pProceduralHitShaders"}))
      type = 3;
    // Defaults apply before reading; a compute pipeline takes no GraphicsPipeline defaults.
    // (Without defaults, the object itself: a copy per pipeline was a good part of reading a large file.)
    const Json* defaults = &defaults_.pipeline;
    Json without_graphics, merged;
    if (type && *type != 0 && defaults->contains("GraphicsPipeline")) {
      without_graphics = *defaults;
      without_graphics.erase("GraphicsPipeline");
      defaults = &without_graphics;
    }
    const Json& j = defaults->empty() ? raw : (merged = merge(*defaults, raw));

    auto pso_desc = j.find("PSODesc");
    if (pso_desc == j.end()) return json_.error(pointer, "a pipeline needs 'PSODesc' with a 'Name'");
    if (!json_.expect_object(*pso_desc, pointer + "/PSODesc", "'PSODesc'")) return;
    json_.check_keys(*pso_desc, pointer + "/PSODesc", schema::kPSODesc, "PSODesc");
    p.name = json_.string(*pso_desc, "Name", pointer + "/PSODesc").value_or("");
    if (p.name.empty()) json_.error(pointer + "/PSODesc", "a pipeline needs a name ('PSODesc.Name')");
    uint32_t unused = 0;
    json_.unsigned_number(*pso_desc, "SRBAllocationGranularity", pointer + "/PSODesc", unused);
    json_.unsigned_number(*pso_desc, "ImmediateContextMask", pointer + "/PSODesc", unused);
    if (auto t = pso_desc->find("PipelineType"); t != pso_desc->end()) {
      auto explicit_type =
          json_.enum_value(*t, pointer + "/PSODesc/PipelineType", kPipelineTypes, "pipeline type");
      if (explicit_type && type && *explicit_type != *type)
        return json_.error(pointer + "/PSODesc/PipelineType",
                           "pipeline '" + p.name + "': PipelineType contradicts the shader slots given");
      if (explicit_type) type = explicit_type;
    }
    if (!type)
      return json_.error(pointer, "pipeline '" + p.name + "' has no shaders, so its type is unknown");
    if (*type >= 2) {
      const char* kinds[] = {"", "", "mesh", "ray-tracing", "tile"};
      return json_.error(pointer, "pipeline '" + p.name + "': " + kinds[*type] +
                                      " pipelines are not supported by the Vulkan backend of statepack");
    }
    p.kind = *type == 1 ? format::PipelineKind::compute : format::PipelineKind::graphics;
    if (p.kind == format::PipelineKind::compute)
      json_.check_keys(j, pointer, schema::kComputePipelineObject, "compute pipeline");
    else
      json_.check_keys(j, pointer, schema::kGraphicsPipelineObject, "graphics pipeline");
    json_.flags_field(j, "Flags", pointer, kPipelineFlags, "pipeline flag", p.flags);
    if (auto s = j.find("ppResourceSignatures"); s != j.end())
      p.signatures = signature_list(*s, pointer + "/ppResourceSignatures");

    static const std::pair<const char*, uint32_t> kSlots[] = {
        {"pVS", VK_SHADER_STAGE_VERTEX_BIT},
        {"pHS", VK_SHADER_STAGE_TESSELLATION_CONTROL_BIT},
        {"pDS", VK_SHADER_STAGE_TESSELLATION_EVALUATION_BIT},
        {"pGS", VK_SHADER_STAGE_GEOMETRY_BIT},
        {"pPS", VK_SHADER_STAGE_FRAGMENT_BIT},
        {"pCS", VK_SHADER_STAGE_COMPUTE_BIT},
    };
    for (const auto& [slot, stage] : kSlots) {
      auto s = j.find(slot);
      if (s == j.end()) continue;
      std::string sp = pointer + "/" + slot;
      if (s->is_string()) {  // a name from the Shaders section, resolved after all files are read
        ShaderDesc ref;
        ref.name = s->get<std::string>();
        ref.stage = stage;
        ref.is_reference = true;
        ref.where = json_.at(sp);
        p.shaders.push_back(std::move(ref));
      } else if (auto shader = shader_object(*s, sp, stage)) {
        p.shaders.push_back(std::move(*shader));
      }
    }
    if (p.kind == format::PipelineKind::graphics && !j.contains("pVS"))
      json_.error(pointer, "graphics pipeline '" + p.name + "' needs a vertex shader ('pVS')");

    if (auto layout = pso_desc->find("ResourceLayout"); layout != pso_desc->end())
      resource_layout(*layout, pointer + "/PSODesc/ResourceLayout", p);
    specialization_constants(j, pointer, p);
    if (auto g = j.find("GraphicsPipeline"); g != j.end()) {
      read_graphics_state(ctx_, *g, pointer + "/GraphicsPipeline", p.graphics, p.subpass, p.input_semantics);
      uint32_t extra = 0;
      json_.flags_field(*g, "DynamicStates", pointer + "/GraphicsPipeline", kDynamicStates, "dynamic state",
                        extra);
      p.dynamic_states |= extra;
      if (auto rp = g->find("pRenderPass"); rp != g->end())
        if (auto name = render_pass_object(*rp, pointer + "/GraphicsPipeline/pRenderPass"))
          p.render_pass = *name;
      if (p.subpass != 0 && !g->contains("pRenderPass"))
        json_.error(
            pointer + "/GraphicsPipeline/SubpassIndex",
            "pipeline '" + p.name + "': 'SubpassIndex' " + std::to_string(p.subpass) +
                " needs a render pass ('pRenderPass'); without one the pipeline uses dynamic rendering");
    }

    // Tessellation stages come in pairs and draw patches, and patches need them (Vulkan's
    // VUID-VkGraphicsPipelineCreateInfo-pStages-00729/00730/00736 and topology-08889).
    if (p.kind == format::PipelineKind::graphics) {
      const bool hull = j.contains("pHS"), domain = j.contains("pDS");
      const bool patches = p.graphics.topology == VK_PRIMITIVE_TOPOLOGY_PATCH_LIST;
      if (hull != domain)
        json_.error(pointer + (hull ? "/pHS" : "/pDS"),
                    "pipeline '" + p.name + "': a " +
                        (hull ? "hull shader needs a domain shader ('pDS')"
                              : "domain shader needs a hull shader ('pHS')"));
      else if (hull && !patches && !names_patch_list(j))
        json_.error(
            pointer + "/GraphicsPipeline/PrimitiveTopology",
            "pipeline '" + p.name +
                "' tessellates (pHS, pDS), so its PrimitiveTopology must be a patch list: "
                "'N_CONTROL_POINT_PATCHLIST' with N the hull shader's input control points (1 to 32)");
      else if (!hull && patches)
        json_.error(
            pointer + "/GraphicsPipeline/PrimitiveTopology",
            "pipeline '" + p.name + "' draws patches, which need tessellation shaders ('pHS', 'pDS')");
    }

    if (!p.name.empty()) {
      auto [it, inserted] = out_.pipeline_index.try_emplace(p.name, out_.pipelines.size());
      if (!inserted)
        return json_.error(pointer, "pipeline '" + p.name + "' is defined twice (first at " +
                                        location_text(out_.pipelines[it->second].where) + ")");
    }
    out_.pipelines.push_back(std::move(p));
  }

 public:
  // Reads a file and what it imports, each file once. Imports are followed with a stack of open files,
  // not by recursion: a chain of thousands of imports is read like any other.
  static void read_files(const fs::path& path, const std::string& display, Notation& out,
                         const NotationOptions& options, Diagnostics& diag, const Location& requested_at) {
    std::vector<std::unique_ptr<OpenFile>> open;
    if (auto first = open_file(path, display, out, options, diag, requested_at, open))
      open.push_back(std::move(first));
    while (!open.empty()) {
      OpenFile& top = *open.back();
      if (top.imports && top.next_import < top.imports->size() && !diag.full()) {
        const size_t i = top.next_import++;
        if (auto imported = top.reader->import_path(*top.imports, i))
          if (auto next = open_file(*imported, display_path(*imported), out, options, diag,
                                    top.reader->import_location(i), open))
            open.push_back(std::move(next));
        continue;
      }
      top.reader->finish(top.doc.root);
      open.pop_back();
    }
  }

 private:
  // A file being read: its document, its reader, and how far its imports have been followed.
  struct OpenFile {
    std::string key;  // its identity (Notation::files_done)
    fs::path canonical;
    JsonDocument doc;
    std::unique_ptr<FileReader> reader;
    const Json* imports = nullptr;
    size_t next_import = 0;
  };

  // Opens and parses a file not read yet; nothing for one read before (a diamond, a repeated -i, another
  // spelling of it), one being read (an import cycle: a warning with its chain, as Diligent skips it) or
  // one that cannot be read (the error reported).
  static std::unique_ptr<OpenFile> open_file(const fs::path& path, const std::string& display, Notation& out,
                                             const NotationOptions& options, Diagnostics& diag,
                                             const Location& imported_at,
                                             const std::vector<std::unique_ptr<OpenFile>>& open) {
    std::error_code ec;
    fs::path canonical = options.memory_files ? path.lexically_normal() : fs::weakly_canonical(path, ec);
    if (ec) canonical = fs::absolute(path, ec).lexically_normal();
    std::string key = "path:" + canonical.string();
    if (!options.memory_files)
      if (auto id = detail::file_identity(path))
        key = "file:" + std::to_string(id->device) + ":" + std::to_string(id->inode);
    auto cycle = std::find_if(open.begin(), open.end(), [&](const auto& f) { return f->key == key; });
    if (cycle != open.end()) {
      std::string chain;
      for (auto it = cycle; it != open.end(); ++it) chain += display_path((*it)->canonical) + " -> ";
      diag.warning(imported_at,
                   "import cycle: " + chain + display_path((*cycle)->canonical) +
                       " (the import is skipped: the file is being read already, as in Diligent)");
      return nullptr;
    }
    if (!out.files_done.insert(key).second) return nullptr;
    InputText input;
    if (options.memory_files) {
      auto it = options.memory_files->find(path.string());
      if (it != options.memory_files->end())
        input.text = it->second;
      else
        input.error = "cannot open '" + path.string() + "': not among the in-memory files";
    } else {
      input = read_input_file(path, display, options.max_input_bytes);
    }
    // The message names the file; a location adds only where it was imported from.
    if (!input.error.empty()) {
      diag.error(imported_at.line > 0 ? imported_at : Location{}, input.error);
      return nullptr;
    }
    out.files_read.push_back({canonical, input.identity});
    auto file = std::make_unique<OpenFile>();
    file->key = std::move(key);
    file->canonical = canonical;
    // Kept for errors found later; positions count after a BOM.
    const std::string_view text = strip_utf8_bom(out.sources.add(display, std::move(input.text)));
    file->doc = parse_json_document(text);
    if (!file->doc.errors.empty()) {
      JsonPositions positions(text);
      for (const auto& e : file->doc.errors) {
        TextPosition at = positions.position_at(e.offset);
        diag.error({display, at.line, at.column, ""}, e.message);
      }
    }
    if (!file->doc.parsed || file->doc.root.empty()) file->doc.root = Json();  // nothing to read
    file->reader = std::make_unique<FileReader>(canonical, display, text, options, out, diag);
    if (file->doc.parsed && !file->doc.root.is_null()) file->imports = file->reader->begin(file->doc.root);
    return file;
  }

 private:
  JsonReader json_;
  ReadContext ctx_;
  Notation& out_;
  const NotationOptions& options_;
  Defaults defaults_;
};

}  // namespace

void read_notation(const fs::path& input, const NotationOptions& options, Notation& notation,
                   Diagnostics& diag) {
  std::error_code ec;
  const fs::path base = options.memory_files ? fs::path() : fs::current_path(ec);
  fs::path path = resolve_file(input.string(), base, options.render_state_dirs, options.memory_files);
  if (path.empty())
    return diag.error({input.string()}, "cannot find render-state file (also searched the -r directories)");
  notation.lookups.push_back({false, input.string(), base, path});
  // Named as imports and shaders are, however the input was spelled: relative to the working directory
  // when below it, so one file has one name in every message.
  FileReader::read_files(path, display_path(path), notation, options, diag, {input.string()});
}

namespace {

// Formats and sample count of a pipeline's subpass, which the render pass decides.
// Errors at the pipeline's SubpassIndex or RTVFormats, where the user wrote them.
void apply_render_pass(const format::RenderPass& rp, PipelineDesc& p, const SourceTexts& sources,
                       Diagnostics& diag) {
  format::GraphicsState& g = p.graphics;
  const std::string gp = p.where.pointer + "/GraphicsPipeline";
  if (p.subpass >= rp.subpasses.size()) {
    diag.error(sources.at(p.where, gp + "/SubpassIndex"), "pipeline '" + p.name + "': render pass '" +
                                                              rp.name + "' has no subpass " +
                                                              std::to_string(p.subpass));
    return;
  }
  const format::Subpass& sp = rp.subpasses[p.subpass];
  std::array<uint32_t, format::kMaxColorTargets> formats{};
  uint32_t samples = 0;
  for (size_t i = 0; i < sp.colors.size(); ++i) {
    if (sp.colors[i].attachment == format::kNone) continue;
    formats[i] = rp.attachments[sp.colors[i].attachment].format;
    samples = rp.attachments[sp.colors[i].attachment].samples;
  }
  uint32_t depth = 0;
  if (sp.depth_stencil.attachment != format::kNone) {
    depth = rp.attachments[sp.depth_stencil.attachment].format;
    samples = rp.attachments[sp.depth_stencil.attachment].samples;
  }
  if (g.color_count != 0 && (g.color_count != sp.colors.size() || g.color_formats != formats))
    diag.error(sources.at(p.where, gp + "/RTVFormats"),
               "pipeline '" + p.name + "': RTVFormats/NumRenderTargets disagree with subpass " +
                   std::to_string(p.subpass) + " of render pass '" + rp.name + "' (" +
                   std::to_string(sp.colors.size()) +
                   " color attachment(s)); leave them out to take the subpass's");
  g.color_count = static_cast<uint32_t>(sp.colors.size());
  g.color_formats = formats;
  g.depth_stencil_format = depth;
  if (samples != 0) g.samples = samples;
}

}  // namespace

void resolve_references(Notation& notation, Diagnostics& diag) {
  // With an import missing, the name may well be defined there: say so instead of suggesting a
  // similar name that is fine (a shader 'Common VS' for the imported 'Common CS').
  auto hint = [&](const std::string& name, const std::vector<std::string>& names) {
    if (notation.failed_imports.empty()) return detail::did_you_mean(name, names);
    return " (perhaps defined in '" + notation.failed_imports.front() + "', which was not found)";
  };
  std::vector<std::string> shader_names, signature_names, pass_names;
  for (const auto& s : notation.shaders) shader_names.push_back(s.name);
  for (const auto& s : notation.inline_shaders) shader_names.push_back(s.name);
  for (const auto& s : notation.signatures) signature_names.push_back(s.name);
  for (const auto& r : notation.render_passes) pass_names.push_back(r.pass.name);
  for (auto& pipeline : notation.pipelines) {
    for (auto& shader : pipeline.shaders) {
      if (!shader.is_reference) continue;
      const ShaderDesc* found = nullptr;
      if (auto it = notation.shader_index.find(shader.name); it != notation.shader_index.end())
        found = &notation.shaders[it->second];
      else if (auto inl = notation.inline_shader_index.find(shader.name);
               inl != notation.inline_shader_index.end())
        found = &notation.inline_shaders[inl->second];
      if (!found) {
        diag.error(shader.where, "pipeline '" + pipeline.name + "' refers to unknown shader '" + shader.name +
                                     "'" + hint(shader.name, shader_names));
        continue;
      }
      if (found->broken) {  // its errors are reported where it is defined
        shader.broken = true;
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
    // An immutable sampler named after a texture applies to its sampler (the name plus the suffix) when
    // the shaders say they use combined samplers (Desc.UseCombinedTextureSamplers), as Diligent marks the
    // implicit layout; they must agree on the suffix.
    pipeline.combined_sampler_suffix.clear();
    const ShaderDesc* suffix_from = nullptr;
    for (const auto& shader : pipeline.shaders) {
      if (shader.combined_sampler_suffix.empty()) continue;
      if (!suffix_from) {
        suffix_from = &shader;
        pipeline.combined_sampler_suffix = shader.combined_sampler_suffix;
      } else if (shader.combined_sampler_suffix != suffix_from->combined_sampler_suffix) {
        diag.error(shader.where, "pipeline '" + pipeline.name + "': shader '" + shader.name +
                                     "' has CombinedSamplerSuffix '" + shader.combined_sampler_suffix +
                                     "' and shader '" + suffix_from->name + "' has '" +
                                     suffix_from->combined_sampler_suffix +
                                     "': the shaders of a pipeline share one suffix");
      }
    }
    for (const auto& name : pipeline.signatures)
      if (!notation.signature_index.count(name))
        diag.error(pipeline.where, "pipeline '" + pipeline.name + "' refers to unknown resource signature '" +
                                       name + "'" + hint(name, signature_names));
    if (!pipeline.render_pass.empty()) {
      auto pass = notation.render_pass_index.find(pipeline.render_pass);
      if (pass == notation.render_pass_index.end())
        diag.error(pipeline.where, "pipeline '" + pipeline.name + "' refers to unknown render pass '" +
                                       pipeline.render_pass + "'" + hint(pipeline.render_pass, pass_names));
      else if (!notation.render_passes[pass->second].broken)
        apply_render_pass(notation.render_passes[pass->second].pass, pipeline, notation.sources, diag);
    }
  }
  for (const auto& name : notation.ignored_signatures)
    if (!notation.signature_index.count(name))
      diag.warning({}, "Ignore.Signatures names '" + name + "', which no file defines");
}

}  // namespace statepack::packager
