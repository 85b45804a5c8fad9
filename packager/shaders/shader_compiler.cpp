#include "shader_compiler.hpp"

// Debian's glslang is built with HLSL support; the header hides the HLSL setters without this.
#define ENABLE_HLSL 1
#include <glslang/Public/ResourceLimits.h>
#include <glslang/Public/ShaderLang.h>
#include <glslang/SPIRV/GlslangToSpv.h>
#include <spirv-tools/libspirv.hpp>
#include <spirv-tools/optimizer.hpp>

#include <vulkan/vulkan_core.h>

#include "allocation_budget.hpp"
#include "directive_lines.hpp"
#include "glslang_tree.hpp"
#include "hlsl_combined_image_samplers.hpp"
#include "hlsl_push_constants.hpp"
#include "hlsl_system_values.hpp"
#include "nesting_bound.hpp"
#include "shader_environment.hpp"
#include "spirv_module_input.hpp"
#include "spirv_passes.hpp"

#include <algorithm>
#include <map>
#include <mutex>
#include <optional>
#include <sstream>

namespace statepack::packager {
namespace fs = std::filesystem;
namespace {

EShLanguage to_glslang_stage(uint32_t stage) {
  switch (stage) {
    case VK_SHADER_STAGE_VERTEX_BIT:
      return EShLangVertex;
    case VK_SHADER_STAGE_TESSELLATION_CONTROL_BIT:
      return EShLangTessControl;
    case VK_SHADER_STAGE_TESSELLATION_EVALUATION_BIT:
      return EShLangTessEvaluation;
    case VK_SHADER_STAGE_GEOMETRY_BIT:
      return EShLangGeometry;
    case VK_SHADER_STAGE_FRAGMENT_BIT:
      return EShLangFragment;
    default:
      return EShLangCompute;
  }
}

// "64 MiB", or the bytes when not whole mebibytes.
std::string size_text(uint64_t bytes) {
  return bytes % (1u << 20) == 0 ? std::to_string(bytes >> 20) + " MiB" : std::to_string(bytes) + " bytes";
}

// What glslang may allocate to parse one shader (allocation_budget.hpp): a floor that holds its
// built-in symbol tables (about 30 MB for the first shader of a stage) and any hand-written shader,
// and a share per byte of source far above what real shaders need (the path tracer's compute shader
// allocates 70 bytes per byte of its source and includes). An exponential macro passes it within
// seconds, at a few hundred MB.
constexpr uint64_t kCompileAllocationFloor = uint64_t(512) << 20;
constexpr uint64_t kCompileAllocationPerByte = 512;

// A file whose brackets nest beyond kMaxBracketDepth, said where the deepest opens.
std::string too_deep(const std::string& file, size_t depth, size_t line) {
  return file + ":" + std::to_string(line) + ": brackets nest " + std::to_string(depth) +
         " deep here; statepack compiles up to " + std::to_string(kMaxBracketDepth) +
         " (glslang's GLSL parser stops there too)";
}

// Expanded #include text per shader beyond --max-input-size (64 MiB by default) is refused: includes
// without guards can otherwise double the source with every level (a includes b twice, b includes c
// twice, ...).

// Resolves #include "x" next to the including file first, then in the -s directories, and records
// every file it opens so the depfile can list it. statepack resolves includes itself, so it also
// refuses include cycles (reported with their chain) and runaway expansion, which glslang would
// follow until memory runs out.
class Includer final : public glslang::TShader::Includer {
 public:
  Includer(const std::vector<fs::path>& dirs, std::vector<InputFile>& files_read, fs::path root_file,
           uint64_t max_bytes)
      : dirs_(dirs), files_read_(files_read), max_bytes_(max_bytes) {
    chain_.push_back(std::move(root_file));
  }

  IncludeResult* includeLocal(const char* header, const char* includer, size_t depth) override {
    return open(header, true, depth, includer);
  }
  IncludeResult* includeSystem(const char* header, const char* includer, size_t depth) override {
    return open(header, false, depth, includer);
  }
  void releaseInclude(IncludeResult* result) override {
    if (!result) return;
    delete static_cast<std::string*>(result->userData);
    delete result;
  }

  // An included file's text by glslang's name for it, kept only for files that spell
  // combinedImageSampler (hlsl_combined_image_samplers.hpp reads the declarations after it).
  const std::string* attribute_text(const std::string& name) const {
    auto it = attribute_texts_.find(name);
    return it == attribute_texts_.end() ? nullptr : &it->second;
  }
  // Each included file raises the compile's allocation budget by its share.
  void set_budget(AllocationBudget* budget) { budget_ = budget; }

  // The first problem that stopped an include, if any; it explains glslang's error better.
  const std::string& problem() const { return problem_; }
  // Whether an included file tests VULKAN or GL_SPIRV.
  bool backend_specific() const { return backend_specific_; }
  std::vector<IncludeRecord>& includes() { return includes_; }

 private:
  IncludeResult* open(const std::string& header, bool local, size_t depth, const char* includer) {
    if (!problem_.empty()) return nullptr;  // one cause, one message
    const std::string includer_name = includer ? includer : "";
    const fs::path path = resolve_include(header, includer_name, local, dirs_);
    if (path.empty()) {  // glslang's own message ("Could not process include directive") says less
      const std::string from = includer && *includer ? std::string(includer) : std::string("the shader");
      problem_ = "#include \"" + header + "\": no such file next to " + from +
                 (dirs_.empty() ? std::string(" (no -s directory given)")
                                : " or in the " + std::to_string(dirs_.size()) + " -s director" +
                                      (dirs_.size() == 1 ? "y" : "ies"));
      return nullptr;
    }
    // `depth` is the nesting of this #include (1 inside the shader itself): the files still open are
    // the first `depth` of the chain.
    chain_.resize(std::min(chain_.size(), std::max<size_t>(depth, 1)));
    std::error_code ec;
    fs::path canonical = fs::weakly_canonical(path, ec);
    if (ec) canonical = path.lexically_normal();
    for (size_t i = 0; i < chain_.size(); ++i) {
      if (chain_[i] != canonical) continue;
      problem_ = "#include cycle: ";
      for (size_t k = i; k < chain_.size(); ++k) problem_ += display_path(chain_[k]) + " -> ";
      problem_ += display_path(canonical);
      return nullptr;
    }
    InputText input = read_input_file(path, display_path(path), max_bytes_);
    if (!input.error.empty()) {
      problem_ = "#include \"" + header + "\": " + input.error;
      return nullptr;
    }
    if (size_t line = 0, nesting = bracket_depth(input.text, &line); nesting > kMaxBracketDepth) {
      problem_ = "#include \"" + header + "\": " + too_deep(display_path(path), nesting, line);
      return nullptr;
    }
    included_bytes_ += input.text.size();
    if (included_bytes_ > max_bytes_) {
      problem_ =
          "#include \"" + header + "\": the includes expand to more than " + size_text(max_bytes_) +
          " of source (files included repeatedly without include guards?; --max-input-size sets the limit)";
      return nullptr;
    }
    if (budget_) budget_->raise(kCompileAllocationPerByte * input.text.size());
    files_read_.push_back({fs::absolute(path, ec).lexically_normal(), input.identity});
    includes_.push_back({header, includer_name, local, path.string(), text_hash(input.text)});
    backend_specific_ = backend_specific_ || tests_backend_macros(input.text);
    chain_.push_back(canonical);
    if (input.text.find("combinedImageSampler") != std::string::npos)
      attribute_texts_[display_path(path)] = input.text;
    auto* owned = new std::string(std::move(input.text));
    // The name glslang puts in its messages (and resolves nested includes against): relative to the
    // working directory when below it, as every other file name in statepack's messages.
    return new IncludeResult(display_path(path), owned->data(), owned->size(), owned);
  }

  const std::vector<fs::path>& dirs_;
  std::vector<InputFile>& files_read_;
  std::vector<fs::path> chain_;  // canonical paths: the shader, then each open #include
  uint64_t max_bytes_;
  uint64_t included_bytes_ = 0;
  AllocationBudget* budget_ = nullptr;
  std::map<std::string, std::string> attribute_texts_;
  std::string problem_;
  bool backend_specific_ = false;
  std::vector<IncludeRecord> includes_;
};

// One line of glslang's log, "ERROR: file:line: message" (or WARNING): where and what, or nullopt for
// other lines. Parsed by hand: std::regex recurses per character and a long log line would exhaust the
// stack. A number instead of a file name is a source-string number: glslang's when `#line N S` (GLSL's
// form) renumbered the source; every string statepack gives glslang is the shader's own file.
struct LogEntry {
  Location where;
  std::string message;
  bool warning = false;
  std::string placed;  // for an entry in the preamble: what wrote that line (locate_in_preamble)
};
std::optional<LogEntry> parse_log_line(std::string_view rest, const std::string& fallback_file) {
  const bool warning = rest.starts_with("WARNING: ");
  if (!warning && !rest.starts_with("ERROR: ")) return std::nullopt;
  rest.remove_prefix(warning ? 9 : 7);
  // "file:line: message": the first ":digits:" after the file name (which may hold colons).
  size_t colon = 0, number_end = 0;
  int line_number = 0;
  for (size_t i = rest.find(':'); i != std::string_view::npos; i = rest.find(':', i + 1)) {
    size_t k = i + 1;
    long value = 0;
    while (k < rest.size() && rest[k] >= '0' && rest[k] <= '9' && k - i < 10)
      value = value * 10 + (rest[k++] - '0');
    if (k > i + 1 && k < rest.size() && rest[k] == ':') {
      colon = i, number_end = k, line_number = int(value);
      break;
    }
  }
  if (number_end == 0) return std::nullopt;
  LogEntry e{{std::string(rest.substr(0, colon)), line_number, 0, ""},
             std::string(rest.substr(std::min(number_end + 1, rest.size()))),
             warning};
  while (!e.message.empty() && e.message.front() == ' ') e.message.erase(e.message.begin());
  while (!e.message.empty() && e.message.back() == ' ') e.message.pop_back();
  if (e.where.file.find_first_not_of("0123456789") == std::string::npos) e.where.file = fallback_file;
  return e;
}

// The variables written with [[vk::combinedImageSampler]], from glslang's warnings that it ignored the
// attribute (hlsl_combined_image_samplers.hpp).
std::vector<std::string> combined_image_samplers_of(glslang::TShader& ts, const std::string& file_name,
                                                    const std::string& source, const Includer& includer) {
  std::vector<AttributeSite> sites;
  std::istringstream lines(ts.getInfoLog());
  for (std::string line; std::getline(lines, line);)
    if (auto e = parse_log_line(line, file_name);
        e && e->warning && e->message == "'combinedImageSampler' : unrecognized attribute")
      sites.push_back({e->where.file, e->where.line});
  if (sites.empty()) return {};
  return combined_image_sampler_variables(ts, sites, [&](const std::string& file) {
    return file == file_name ? &source : includer.attribute_text(file);
  });
}

// A shader that defines a name the environment defines differently: say where the other definition
// comes from ("'#define' : Macro redefined; different substitutions: HLSL").
std::string environment_hint(const std::string& message, const ShaderDesc& shader,
                             const CompileOptions& options) {
  constexpr std::string_view kRedefined = "Macro redefined; different substitutions: ";
  const size_t at = message.find(kRedefined);
  if (at == std::string::npos) return "";
  std::string name = message.substr(at + kRedefined.size());
  while (!name.empty() && (name.back() == ' ' || name.back() == '\r')) name.pop_back();
  if (!environment_defines(shader, options, name)) return "";
  if (name == "VULKAN")
    return " (glslang defines VULKAN as 100 when it compiles for Vulkan; test it with #ifdef)";
  return " (statepack defines " + name +
         " before every shader, as Diligent does: docs/notation.md, \"The shader environment\"; "
         "--shader-environment none leaves it out)";
}

// An entry glslang places in the preamble (its source string -1, a place no user can find): moved to
// what wrote that line, the notation's Macros entry or GLSLExtensions where they are written, else the
// shader, and named in the message.
void locate_in_preamble(LogEntry& e, const ShaderEnvironment& environment, const ShaderDesc& shader,
                        const CompileOptions& options) {
  if (e.where.file != "-1") return;
  using Kind = PreambleSource::Kind;
  const PreambleSource* source = preamble_source(environment, e.where.line);
  const Kind kind = source ? source->kind : Kind::environment;
  const size_t i = source ? source->index : 0;
  std::string what = "the shader environment";
  e.where = shader.where;
  if (kind == Kind::glsl_extensions) {
    what = "GLSLExtensions";
    if (!shader.extensions_where.file.empty()) e.where = shader.extensions_where;
  } else if (kind == Kind::global_macro && i < options.global_macros.size()) {
    what = "-D " + options.global_macros[i].first;
  } else if (kind == Kind::macro && i < shader.macros.size()) {
    what = "the Macros entry '" + shader.macros[i].first + "'";
    if (i < shader.macro_where.size() && !shader.macro_where[i].file.empty()) e.where = shader.macro_where[i];
  }
  e.placed = " (in " + what + ", which statepack puts before the shader's first line)";
}

// Turns each error of glslang's log into a diagnostic at its file and line.
void report_log(const std::string& log, const ShaderDesc& shader, ShaderMessages& messages,
                const std::string& fallback_file, const CompileOptions& options,
                const ShaderEnvironment& environment) {
  std::vector<LogEntry> errors;
  std::istringstream lines(log);
  for (std::string line; std::getline(lines, line);)
    if (auto e = parse_log_line(line, fallback_file);
        e && !e->warning && e->message.find("compilation terminated") == std::string::npos) {
      locate_in_preamble(*e, environment, shader, options);
      errors.push_back(std::move(*e));
    }
  // glslang stops parsing at an error inside #if, then finds the #if unclosed: "missing #endif" follows
  // every such error. Said alone it is the mistake; beside another error, a consequence.
  const bool other_errors = std::any_of(errors.begin(), errors.end(), [](const LogEntry& e) {
    return e.message.find("missing #endif") == std::string::npos;
  });
  bool any = false;
  Location last_extension;  // where glslang last refused an #extension
  size_t order = 0;
  for (const LogEntry& e : errors) {
    // glslang follows an unknown #extension with "extra tokens" on the same line: its parser stops at
    // the name, so the rest of the directive looks like junk. One mistake, one error.
    if (e.message.starts_with("'#extension' : extra tokens") && e.where.file == last_extension.file &&
        e.where.line == last_extension.line)
      continue;
    if (e.message.starts_with("'#extension' : extension not supported")) last_extension = e.where;
    if (other_errors && e.message.find("missing #endif") != std::string::npos) continue;
    messages.error(e.where, shader.name, e.message + e.placed + environment_hint(e.message, shader, options),
                   order++);
    any = true;
  }
  if (!any) {
    std::string trimmed = log;
    while (!trimmed.empty() && (trimmed.back() == '\n' || trimmed.back() == ' ')) trimmed.pop_back();
    if (trimmed.empty()) trimmed = "compilation failed";
    messages.error(shader.where, shader.name, trimmed);
  }
}

void initialize_glslang() {
  static std::once_flag initialized;
  std::call_once(initialized, [] { glslang::InitializeProcess(); });
}

// OpenGL 4.5 with GL_ARB_gl_spirv: glslang's OpenGL client, SPIR-V 1.0.
void target_opengl(glslang::TShader& ts, EShLanguage stage) {
  ts.setEnvInput(glslang::EShSourceGlsl, stage, glslang::EShClientOpenGL, 450);
  ts.setEnvClient(glslang::EShClientOpenGL, glslang::EShTargetOpenGL_450);
  ts.setEnvTarget(glslang::EShTargetSpv, glslang::EShTargetSpv_1_0);
}

// The client and SPIR-V version glslang compiles for: --vulkan_version, or OpenGL 4.5.
void set_target(glslang::TShader& ts, EShLanguage stage, bool hlsl, const CompileOptions& options) {
  if (options.opengl) return target_opengl(ts, stage);
  const uint32_t minor = options.vulkan_version >> 12 & 0x3FF;
  const auto client = minor >= 3   ? glslang::EShTargetVulkan_1_3
                      : minor == 2 ? glslang::EShTargetVulkan_1_2
                      : minor == 1 ? glslang::EShTargetVulkan_1_1
                                   : glslang::EShTargetVulkan_1_0;
  const auto spirv_version = minor >= 3   ? glslang::EShTargetSpv_1_6
                             : minor == 2 ? glslang::EShTargetSpv_1_5
                             : minor == 1 ? glslang::EShTargetSpv_1_3
                                          : glslang::EShTargetSpv_1_0;
  ts.setEnvInput(hlsl ? glslang::EShSourceHlsl : glslang::EShSourceGlsl, stage, glslang::EShClientVulkan,
                 100);
  ts.setEnvClient(glslang::EShClientVulkan, client);
  ts.setEnvTarget(glslang::EShTargetSpv, spirv_version);
}

// A parsed shader linked on its own and turned into SPIR-V (glslang's optimizer off: SPIRV-Tools
// finalises the module later). On failure `spirv` is empty and `link_log` (glslang's link messages) or
// `generation_error` says why.
struct LinkedSpirv {
  std::vector<uint32_t> spirv;
  std::string link_log, generation_error;
};
// Parses (preprocesses) `ts` under an allocation budget for `source_bytes` of source (each #include
// adds its own share). Returns the error when the budget ran out, else "" with `parsed` set.
std::string parse_within_budget(glslang::TShader& ts, EShMessages messages, Includer& includer,
                                size_t source_bytes, int default_version, bool& parsed) {
  AllocationBudget budget(kCompileAllocationFloor + kCompileAllocationPerByte * source_bytes);
  includer.set_budget(&budget);
  try {
    parsed = ts.parse(GetDefaultResources(), default_version, false, messages, includer);
  } catch (const std::bad_alloc&) {
    if (!budget.exhausted()) throw;
  }
  includer.set_budget(nullptr);
  if (!budget.exhausted()) return "";
  return "compiling it allocated more than " + std::to_string(budget.limit() >> 20) + " MiB (" +
         std::to_string(kCompileAllocationFloor >> 20) + " MiB and " +
         std::to_string(kCompileAllocationPerByte) +
         " bytes per byte of source and includes): does a macro expand exponentially, such as one used twice "
         "in the next one's definition, or F(F(F(...))) with F using its argument twice?";
}

LinkedSpirv link_to_spirv(glslang::TShader& ts, EShLanguage stage, EShMessages messages) {
  LinkedSpirv out;
  glslang::TProgram program;
  program.addShader(&ts);
  if (!program.link(messages) || !program.mapIO()) {
    out.link_log = program.getInfoLog();
    return out;
  }
  glslang::SpvOptions spv_options;
  spv_options.disableOptimizer = true;
  spv::SpvBuildLogger logger;
  glslang::GlslangToSpv(*program.getIntermediate(stage), out.spirv, &logger, &spv_options);
  if (out.spirv.empty()) out.generation_error = "SPIR-V generation failed: " + logger.getAllMessages();
  return out;
}

}  // namespace

// What glslang's HLSL parse tree shows and its messages do not: [[vk::push_constant]] globals it made
// uniforms, system values it made varyings. Returns whether it reported any.
bool report_hlsl_tree_problems(const glslang::TShader& ts, const ShaderDesc& shader, ShaderMessages& errors,
                               const std::string& file_name, const std::string& source) {
  bool any = false;
  for (const auto& pc : find_misplaced_push_constants(ts)) {
    const std::string type = pc.type.empty() ? "S" : pc.type;
    errors.error({pc.file.empty() ? file_name : pc.file, pc.line, 0, ""}, shader.name,
                 "[[vk::push_constant]] on the global variable '" + pc.variable +
                     "' is not a push constant for glslang (it would become a member of the $Global "
                     "uniform buffer); declare it as '[[vk::push_constant]] ConstantBuffer<" +
                     type + "> " + pc.variable + ";' or as a '[[vk::push_constant]] cbuffer'");
    any = true;
  }
  for (auto sv : find_unknown_system_values(ts)) {
    // An entry point's parameters become variables glslang places nowhere, and it upper-cases the
    // semantic: the first place the shader's own text spells it gives the line and the spelling.
    if (sv.line == 0) {
      std::string upper = source;
      for (char& c : upper) c = char(std::toupper(static_cast<unsigned char>(c)));
      if (size_t at = upper.find(sv.semantic); at != std::string::npos) {
        sv.file = file_name;
        sv.line = 1 + int(std::count(source.begin(), source.begin() + std::ptrdiff_t(at), '\n'));
        sv.semantic = source.substr(at, sv.semantic.size());
      }
    }
    const std::string direction = sv.output ? "output" : "input";
    errors.error({sv.file.empty() ? file_name : sv.file, sv.line, 0, ""}, shader.name,
                 "'" + sv.variable + "' has the system value " + sv.semantic +
                     ", which glslang (the HLSL compiler statepack uses) does not know: it would become an "
                     "ordinary " +
                     direction + " with a location, which " +
                     (sv.output ? "no later stage reads as that value"
                                : "no InputLayout or earlier stage can provide") +
                     "; compute the value another way (DXC knows more system values than glslang)");
    any = true;
  }
  return any;
}

namespace {

// The shader's text (its file's, or its inline Source) and the name messages give it; false when the
// file cannot be read (reported).
bool read_shader_source(const ShaderDesc& shader, const std::string& inline_name,
                        const CompileOptions& options, CompiledShader& result, std::string& source,
                        std::string& file_name, ShaderMessages& errors) {
  source = shader.source;
  file_name = "<inline source of '" + inline_name + "'>";
  if (!shader.file.empty()) {
    InputText input = read_input_file(shader.file, display_path(shader.file), options.max_input_bytes);
    if (!input.error.empty()) {
      errors.error(shader.where, shader.name, input.error);
      return false;
    }
    source = std::move(input.text);
    file_name = display_path(shader.file);
    std::error_code ec;
    result.files_read.push_back({fs::absolute(shader.file, ec).lexically_normal(), input.identity});
  }
  if (source.size() > size_t(INT32_MAX)) {  // glslang takes int lengths
    errors.error(shader.where, shader.name, "the source is too large");
    return false;
  }
  return true;
}

// Everything glslang is told besides the text: entry point, environment, target, HLSL's conventions.
void configure(glslang::TShader& ts, const ShaderDesc& shader, const CompileOptions& options,
               EShLanguage stage, const std::string& preamble) {
  const bool hlsl = shader.language == SourceLanguage::hlsl;
  ts.setEntryPoint(shader.entry_point.c_str());
  ts.setSourceEntryPoint(shader.entry_point.c_str());
  ts.setPreamble(preamble.c_str());
  set_target(ts, stage, hlsl, options);
  if (hlsl) {
    ts.setHlslIoMapping(true);
    // SV_Position.w in a pixel shader is the clip-space w, as in Direct3D (and Diligent), not 1/w.
    ts.setDxPositionW(true);
    // Its UserSemantic decorations tell the vertex inputs' semantics (hlsl_vertex_inputs.hpp); the
    // extension is stripped once they are read, as no driver needs it.
    ts.setEnvTargetHlslFunctionality1();
  }
  ts.setAutoMapBindings(true);  // resources without explicit bindings get one; the layout step finalises them
}

// A parse that failed: the #include problem that stopped it, at the #include, or glslang's errors.
void report_parse_failure(glslang::TShader& ts, const Includer& includer, const ShaderDesc& shader,
                          const std::string& file_name, const CompileOptions& options,
                          const ShaderEnvironment& environment, ShaderMessages& errors) {
  if (includer.problem().empty())
    return report_log(ts.getInfoLog(), shader, errors, file_name, options, environment);
  // The cause, at the #include glslang stopped at (its first error), and nothing that followed.
  Location where = shader.where;
  std::istringstream lines(ts.getInfoLog());
  for (std::string line; std::getline(lines, line);)
    if (auto e = parse_log_line(line, file_name); e && !e->warning) {
      locate_in_preamble(*e, environment, shader, options);
      where = e->where;
      break;
    }
  errors.error(where, shader.name, includer.problem());
}

// GLSLVersion and a #version in the file that says otherwise: Diligent writes "#version" from
// GLSLVersion itself, so a file with another one would not compile there. True when they disagree.
bool version_clash(glslang::TShader& ts, const ShaderDesc& shader, const std::string& file_name,
                   ShaderMessages& errors) {
  if (shader.language != SourceLanguage::glsl || shader.glsl_version == 0) return false;
  const int version = ts.getIntermediate()->getVersion();
  if (version == int(shader.glsl_version)) return false;
  errors.error(shader.where, shader.name,
               "'GLSLVersion' asks for GLSL " + std::to_string(shader.glsl_version / 100) + "." +
                   std::to_string(shader.glsl_version / 10 % 10) + "0, but " + file_name + " says #version " +
                   std::to_string(version) +
                   " (Diligent adds the #version line itself; drop one of the two)");
  return true;
}

// A BYTECODE shader: the file's SPIR-V, taken as a compile's result (spirv_module_input.hpp).
bool take_bytecode(const ShaderDesc& shader, const CompileOptions& options, const std::string& bytes,
                   const std::string& file_name, CompiledShader& result, ShaderMessages& errors) {
  SpirvModuleInput module;
  if (std::string problem = take_spirv_module(bytes, shader, options, module); !problem.empty()) {
    errors.error(shader.where, shader.name, file_name + " " + problem);
    return false;
  }
  result.spirv = std::move(module.words);
  result.entry_point = std::move(module.entry_point);
  result.vertex_semantics = std::move(module.semantics);
  return true;
}

// Why the shader nests too deeply to compile (nesting_bound.hpp), or "": its own text's brackets, then
// the preprocessed text's statements (macros expanded, #includes in), measured on a preprocessing pass
// of its own before the parse that recurses. A text that fails to preprocess is left to that parse to
// report.
std::string nesting_problem(const ShaderDesc& shader, const CompileOptions& options, EShLanguage stage,
                            const ShaderEnvironment& environment, const char* const* strings,
                            const int* lengths, const char* const* names, EShMessages messages,
                            size_t budgeted, bool hlsl, const std::string& file_name,
                            const std::string& source) {
  if (size_t line = 0, depth = bracket_depth(source, &line); depth > kMaxBracketDepth)
    return too_deep(file_name, depth, line);
  if (within_bound_unpreprocessed(source, environment.preamble)) return "";  // (no macros, no #include)
  glslang::TShader ts(stage);
  ts.setStringsWithLengthsAndNames(strings, lengths, names, 1);
  configure(ts, shader, options, stage, environment.preamble);
  std::vector<InputFile> files_read;
  std::error_code ec;
  Includer includer(options.include_dirs, files_read,
                    shader.file.empty() ? fs::path() : fs::weakly_canonical(shader.file, ec),
                    options.max_input_bytes);
  std::string preprocessed;
  bool ok = false;
  {
    AllocationBudget budget(kCompileAllocationFloor + kCompileAllocationPerByte * budgeted);
    includer.set_budget(&budget);
    try {
      ok = ts.preprocess(GetDefaultResources(), hlsl ? 450 : environment.default_glsl_version, ENoProfile,
                         false, false, messages, &preprocessed, includer);
    } catch (const std::bad_alloc&) {
      if (!budget.exhausted()) throw;
      ok = false;  // the parse meets the same budget and says so
    }
    includer.set_budget(nullptr);
  }
  if (!ok) return "";  // the parse meets the same problem (an #include too, refused there by name)
  if (size_t bound = nesting_bound(preprocessed); bound > kMaxNesting)
    return "nests too deeply to compile safely: after its macros and #includes, its statements and brackets "
           "measure " +
           std::to_string(bound) +
           " (an expression chain such as v+v+... counts each operand); statepack "
           "compiles up to " +
           std::to_string(kMaxNesting);
  return "";
}

// A GLSL text's #version directive line ("#version 450 core"), or "" when it has none: the first
// directive line that is #version, of at most 200 characters.
std::string version_line(std::string_view source) {
  std::string out;
  for_each_directive(source, [&](std::string_view directive, std::string_view line) {
    if (!directive.starts_with("version")) return false;
    if (line.size() <= 200) out = std::string(line) + '\n';
    return true;
  });
  return out;
}

// What glslang is asked to check and report (prepare_compiler asks the same: it is part of the key of
// glslang's built-in tables). EShMsgEnhanced: the first error only. glslang stops at the first error of a
// file but not of an #include: after an error in the included file it went on to report a confused
// second one at the includer's line after the #include; HLSL also adds follow-on errors ("Could not
// perform requested binary operation") to the one that matters.
EShMessages compile_messages(bool hlsl, const CompileOptions& options) {
  return static_cast<EShMessages>(EShMsgSpvRules | (options.opengl ? 0 : int(EShMsgVulkanRules)) |
                                  EShMsgEnhanced | (hlsl ? int(EShMsgReadHlsl) : 0));
}

// glslang from source to linked, legalized SPIR-V in `result`; false with the errors reported.
bool compile_source(const ShaderDesc& shader, const CompileOptions& options, const std::string& source,
                    const std::string& file_name, CompiledShader& result, ShaderMessages& errors) {
  const EShLanguage stage = to_glslang_stage(shader.stage);
  const bool hlsl = shader.language == SourceLanguage::hlsl;
  glslang::TShader ts(stage);
  const char* strings[] = {source.c_str()};
  const int lengths[] = {static_cast<int>(source.size())};
  const char* names[] = {file_name.c_str()};
  ts.setStringsWithLengthsAndNames(strings, lengths, names, 1);
  ShaderEnvironment environment = shader_environment(shader, options);
  // GLSL that enables #include as GL_ARB_shading_language_include (Diligent's spelling) gets the name
  // this glslang knows too; its own #extension line stays a warning glslang does not report here.
  if (!hlsl && source.find("GL_ARB_shading_language_include") != std::string::npos)
    prepend_to_preamble(environment, "#extension GL_GOOGLE_include_directive : enable\n");
  configure(ts, shader, options, stage, environment.preamble);
  const EShMessages messages = compile_messages(hlsl, options);
  std::error_code ec;
  Includer includer(options.include_dirs, result.files_read,
                    shader.file.empty() ? fs::path() : fs::weakly_canonical(shader.file, ec),
                    options.max_input_bytes);
  const size_t budgeted = source.size() + environment.preamble.size() - environment.fixed_bytes;
  if (std::string too_nested = nesting_problem(shader, options, stage, environment, strings, lengths, names,
                                               messages, budgeted, hlsl, file_name, source);
      !too_nested.empty()) {
    errors.error(shader.where, shader.name, too_nested);
    return false;
  }
  bool parsed = false;
  if (std::string exhausted = parse_within_budget(ts, messages, includer, budgeted,
                                                  hlsl ? 450 : environment.default_glsl_version, parsed);
      !exhausted.empty()) {
    errors.error(shader.where, shader.name, exhausted);
    return false;
  }
  if (!parsed) {
    report_parse_failure(ts, includer, shader, file_name, options, environment, errors);
    return false;
  }
  if (hlsl && report_hlsl_tree_problems(ts, shader, errors, file_name, source)) return false;
  if (version_clash(ts, shader, file_name, errors)) return false;
  if (hlsl) result.combined_image_samplers = combined_image_samplers_of(ts, file_name, source, includer);
  LinkedSpirv linked = link_to_spirv(ts, stage, messages);
  if (!linked.link_log.empty()) {
    report_log(linked.link_log, shader, errors, file_name, options, environment);
    return false;
  }
  if (!linked.generation_error.empty()) {
    errors.error(shader.where, shader.name, linked.generation_error);
    return false;
  }
  result.spirv = std::move(linked.spirv);
  result.entry_point = shader.entry_point;
  if (hlsl)
    if (std::string error =
            legalize_hlsl(result.spirv, options, stage == EShLangVertex, result.vertex_semantics);
        !error.empty()) {
      errors.error(shader.where, shader.name, error);
      return false;
    }
  result.backend_specific = !hlsl && (tests_backend_macros(source) || includer.backend_specific());
  result.includes = std::move(includer.includes());
  return true;
}

}  // namespace

std::string unit_key(const ShaderDesc& s) {
  std::string key = std::to_string(s.stage) + '\0' + std::to_string(int(s.language)) + '\0' + s.entry_point +
                    '\0' + s.file.string() + '\0' + s.source + '\0' + std::to_string(s.verbatim) + '\0' +
                    std::to_string(s.compile_flags) + '\0' + s.glsl_extensions + '\0' +
                    std::to_string(s.glsl_version) + '\0' + std::to_string(s.optimize);
  for (const auto& [name, value] : s.macros) key += '\0' + name + '=' + value;
  return key;
}

std::string tables_version_line(const ShaderDesc& shader, const CompileOptions& options) {
  if (shader.language != SourceLanguage::glsl) return "";
  if (shader.file.empty()) return version_line(shader.source);
  return version_line(read_input_file(shader.file, display_path(shader.file), options.max_input_bytes).text);
}

void prepare_compiler(const ShaderDesc& shader, const CompileOptions& options) {
  if (shader.language == SourceLanguage::spirv) return;
  const bool hlsl = shader.language == SourceLanguage::hlsl;
  // Only the #version line (GLSL): it picks the tables; the shader's text is for its compile, which
  // checks how deeply it nests before glslang recurses through it.
  const std::string text = tables_version_line(shader, options);
  initialize_glslang();
  const EShLanguage stage = to_glslang_stage(shader.stage);
  glslang::TShader ts(stage);
  const char* strings[] = {text.c_str()};
  ts.setStrings(strings, 1);
  const ShaderEnvironment environment = shader_environment(shader, options);
  configure(ts, shader, options, stage, "");
  glslang::TShader::ForbidIncluder no_includes;
  std::string preprocessed;
  ts.preprocess(GetDefaultResources(), hlsl ? 450 : environment.default_glsl_version, ENoProfile, false,
                false, compile_messages(hlsl, options), &preprocessed, no_includes);
}

CompiledShader compile_shader(const ShaderDesc& original, const CompileOptions& options,
                              ShaderMessages& errors) {
  initialize_glslang();
  CompiledShader result;
  // The OpenGL compile's messages say so: the same source may compile for Vulkan and fail for OpenGL.
  ShaderDesc renamed;
  if (options.opengl) {
    renamed = original;
    renamed.name += kOpenGlCompile;
  }
  const ShaderDesc& shader = options.opengl ? renamed : original;
  std::string source, file_name;
  if (!read_shader_source(shader, original.name, options, result, source, file_name, errors)) return result;
  const bool taken = shader.language == SourceLanguage::spirv
                         ? take_bytecode(shader, options, source, file_name, result, errors)
                         : compile_source(shader, options, source, file_name, result, errors);
  if (!taken) return result;
  result.source_hash = text_hash(source);
  // A resource counts as used by what the entry point statically uses: glslang keeps every global of
  // the source (one HLSL file often holds VSMain and PSMain with disjoint resources), so module-scope
  // variables nothing references are removed before reflection decides the layout.
  if (std::string error = remove_unused_globals(result.spirv, options); !error.empty()) {
    errors.error(shader.where, shader.name, error);
    return result;
  }
  result.ok = true;
  return result;
}

CompiledShader compile_shader(const ShaderDesc& shader, const CompileOptions& options, Diagnostics& diag) {
  ShaderMessages errors;
  CompiledShader result = compile_shader(shader, options, errors);
  errors.report(diag);
  return result;
}

fs::path resolve_include(const std::string& header, const std::string& includer, bool local,
                         const std::vector<fs::path>& include_dirs) {
  return resolve_file(header, local ? fs::path(includer).parent_path() : fs::path(), include_dirs);
}

Digest text_hash(std::string_view text) {
  return sha256(text);
}

bool tests_backend_macros(std::string_view text) {
  return for_each_directive(text, [](std::string_view directive, std::string_view) {
    if (!directive.starts_with("if") && !directive.starts_with("elif")) return false;  // #if, #ifdef, #ifndef
    for (std::string_view name : {std::string_view("VULKAN"), std::string_view("GL_SPIRV")})
      for (size_t at = directive.find(name); at != std::string_view::npos;
           at = directive.find(name, at + 1)) {
        auto word = [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; };
        const bool starts = at == 0 || !word(directive[at - 1]);
        const bool ends = at + name.size() == directive.size() || !word(directive[at + name.size()]);
        if (starts && ends) return true;
      }
    return false;
  });
}

std::vector<uint32_t> compile_generated_glsl(const std::string& glsl, uint32_t vk_stage, std::string& log) {
  initialize_glslang();
  const EShLanguage stage = to_glslang_stage(vk_stage);
  glslang::TShader ts(stage);
  const char* strings[] = {glsl.c_str()};
  ts.setStrings(strings, 1);
  ts.setEntryPoint("main");
  target_opengl(ts, stage);
  const auto messages = static_cast<EShMessages>(EShMsgSpvRules | EShMsgEnhanced);
  glslang::TShader::ForbidIncluder no_includes;
  if (!ts.parse(GetDefaultResources(), 450, false, messages, no_includes)) {
    log = ts.getInfoLog();
    return {};
  }
  LinkedSpirv linked = link_to_spirv(ts, stage, messages);
  log = linked.link_log.empty() ? linked.generation_error : linked.link_log;
  return std::move(linked.spirv);
}

std::string finalize_spirv(std::vector<uint32_t>& spirv, const CompileOptions& options) {
  const spv_target_env env = target_env(options);
  std::string messages;
  // SPIRV-Tools messages span lines (the message, then the instruction); one diagnostic line each.
  auto consumer = [&](spv_message_level_t, const char*, const spv_position_t& pos, const char* message) {
    std::string text = message;
    for (char& ch : text)
      if (ch == '\n') ch = ' ';
    while (!text.empty() && text.back() == ' ') text.pop_back();
    messages += (messages.empty() ? "" : "; ") + ("word " + std::to_string(pos.index) + ": " + text);
  };
  if (options.optimization != Optimization::none || options.strip_debug_info) {
    spvtools::Optimizer optimizer(env);
    optimizer.SetMessageConsumer(consumer);
    if (options.optimization == Optimization::speed) optimizer.RegisterPerformancePasses();
    if (options.optimization == Optimization::size) optimizer.RegisterSizePasses();
    if (options.strip_debug_info) optimizer.RegisterPass(spvtools::CreateStripDebugInfoPass());
    std::vector<uint32_t> optimized;
    if (!optimizer.Run(spirv.data(), spirv.size(), &optimized))
      return "the SPIR-V optimizer failed: " + messages;
    spirv = std::move(optimized);
  }
  spvtools::SpirvTools tools(env);
  tools.SetMessageConsumer(consumer);
  if (!tools.Validate(spirv)) return "the SPIR-V fails validation: " + messages;
  return "";
}

std::string validate_spirv(const std::vector<uint32_t>& spirv, const CompileOptions& options) {
  CompileOptions validate_only = options;
  validate_only.optimization = Optimization::none;
  validate_only.strip_debug_info = false;
  std::vector<uint32_t> copy = spirv;
  return finalize_spirv(copy, validate_only);
}

std::string disassemble_spirv(const std::vector<uint32_t>& spirv, const CompileOptions& options) {
  spvtools::SpirvTools tools(target_env(options));
  std::string text;
  tools.Disassemble(spirv, &text,
                    SPV_BINARY_TO_TEXT_OPTION_FRIENDLY_NAMES | SPV_BINARY_TO_TEXT_OPTION_INDENT);
  return text;
}

}  // namespace statepack::packager
