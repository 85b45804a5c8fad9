#include "shader_compiler.hpp"

// Debian's glslang is built with HLSL support; the header hides the HLSL setters without this.
#define ENABLE_HLSL 1
#include <glslang/Public/ResourceLimits.h>
#include <glslang/Public/ShaderLang.h>
#include <glslang/SPIRV/GlslangToSpv.h>
#include <spirv-tools/libspirv.hpp>
#include <spirv-tools/optimizer.hpp>

#include <vulkan/vulkan_core.h>

#include <fstream>
#include <mutex>
#include <optional>
#include <regex>
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

std::optional<std::string> read_text(const fs::path& path) {
  std::ifstream file(path, std::ios::binary);
  if (!file) return std::nullopt;
  std::stringstream buffer;
  buffer << file.rdbuf();
  return buffer.str();
}

// Resolves #include "x" next to the including file first, then in the -s directories, and records
// every file it opens so the depfile can list it.
class Includer final : public glslang::TShader::Includer {
 public:
  Includer(const std::vector<fs::path>& dirs, std::vector<fs::path>& files_read)
      : dirs_(dirs), files_read_(files_read) {}

  IncludeResult* includeLocal(const char* header, const char* includer, size_t) override {
    fs::path base = fs::path(includer).parent_path();
    return open(resolve_file(header, base, dirs_));
  }
  IncludeResult* includeSystem(const char* header, const char*, size_t) override {
    return open(resolve_file(header, fs::path(), dirs_));
  }
  void releaseInclude(IncludeResult* result) override {
    if (!result) return;
    delete static_cast<std::string*>(result->userData);
    delete result;
  }

 private:
  IncludeResult* open(const fs::path& path) {
    if (path.empty()) return nullptr;  // glslang reports "cannot find include file"
    auto text = read_text(path);
    if (!text) return nullptr;
    files_read_.push_back(fs::absolute(path).lexically_normal());
    auto* owned = new std::string(std::move(*text));
    return new IncludeResult(path.string(), owned->data(), owned->size(), owned);
  }

  const std::vector<fs::path>& dirs_;
  std::vector<fs::path>& files_read_;
};

// glslang logs "ERROR: file:line: message"; turn each into a diagnostic at that file and line.
void report_log(const std::string& log, const ShaderDesc& shader, Diagnostics& diag,
                const std::string& fallback_file) {
  static const std::regex kLine(R"(^(ERROR|WARNING): (.*?):(\d+): (.*)$)");
  std::istringstream lines(log);
  std::string line;
  bool any = false;
  while (std::getline(lines, line)) {
    std::smatch m;
    if (!std::regex_match(line, m, kLine)) continue;
    if (m[1] == "WARNING" || m[4].str().find("compilation terminated") != std::string::npos) continue;
    Location where{m[2].str(), std::stoi(m[3].str()), 0, ""};
    if (where.file.empty() || where.file == "0") where.file = fallback_file;
    std::string message = m[4].str();
    while (!message.empty() && message.back() == ' ') message.pop_back();
    diag.error(where, "shader '" + shader.name + "': " + message);
    any = true;
  }
  if (!any) {
    std::string trimmed = log;
    while (!trimmed.empty() && (trimmed.back() == '\n' || trimmed.back() == ' ')) trimmed.pop_back();
    if (trimmed.empty()) trimmed = "compilation failed";
    diag.error(shader.where, "shader '" + shader.name + "': " + trimmed);
  }
}

spv_target_env target_env(uint32_t vulkan_version) {
  switch (vulkan_version >> 12 & 0x3FF) {  // minor of VK_MAKE_API_VERSION
    case 0:
      return SPV_ENV_VULKAN_1_0;
    case 1:
      return SPV_ENV_VULKAN_1_1;
    case 2:
      return SPV_ENV_VULKAN_1_2;
    default:
      return SPV_ENV_VULKAN_1_3;
  }
}

}  // namespace

CompiledShader compile_shader(const ShaderDesc& shader, const CompileOptions& options, Diagnostics& diag) {
  static std::once_flag initialized;
  std::call_once(initialized, [] { glslang::InitializeProcess(); });

  CompiledShader result;
  std::string source = shader.source;
  std::string file_name = "<inline source of '" + shader.name + "'>";
  if (!shader.file.empty()) {
    auto text = read_text(shader.file);
    if (!text) {
      diag.error(shader.where, "cannot read shader file '" + shader.file.string() + "'");
      return result;
    }
    source = std::move(*text);
    file_name = display_path(shader.file);
    result.files_read.push_back(fs::absolute(shader.file).lexically_normal());
  }

  const EShLanguage stage = to_glslang_stage(shader.stage);
  const bool hlsl = shader.language == SourceLanguage::hlsl;
  glslang::TShader ts(stage);
  const char* strings[] = {source.c_str()};
  const int lengths[] = {static_cast<int>(source.size())};
  const char* names[] = {file_name.c_str()};
  ts.setStringsWithLengthsAndNames(strings, lengths, names, 1);
  ts.setEntryPoint(shader.entry_point.c_str());
  ts.setSourceEntryPoint(shader.entry_point.c_str());
  std::string preamble;
  for (const auto& [name, value] : options.global_macros) preamble += "#define " + name + " " + value + "\n";
  for (const auto& [name, value] : shader.macros) preamble += "#define " + name + " " + value + "\n";
  ts.setPreamble(preamble.c_str());
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
  // No setEnvTargetHlslFunctionality1: its SPV_GOOGLE_hlsl_functionality1 decorations need a device
  // extension that many drivers (lavapipe included) lack, and Vulkan does not use them.
  if (hlsl) ts.setHlslIoMapping(true);
  ts.setAutoMapBindings(true);  // resources without explicit bindings get one; the layout step finalises them
  auto messages =
      static_cast<EShMessages>(EShMsgSpvRules | EShMsgVulkanRules | (hlsl ? int(EShMsgReadHlsl) : 0));
  Includer includer(options.include_dirs, result.files_read);
  if (!ts.parse(GetDefaultResources(), 450, false, messages, includer)) {
    report_log(ts.getInfoLog(), shader, diag, file_name);
    return result;
  }
  glslang::TProgram program;
  program.addShader(&ts);
  if (!program.link(messages) || !program.mapIO()) {
    report_log(program.getInfoLog(), shader, diag, file_name);
    return result;
  }
  glslang::SpvOptions spv_options;
  spv_options.disableOptimizer = true;
  spv::SpvBuildLogger logger;
  glslang::GlslangToSpv(*program.getIntermediate(stage), result.spirv, &logger, &spv_options);
  if (auto messages_text = logger.getAllMessages(); result.spirv.empty()) {
    diag.error(shader.where, "shader '" + shader.name + "': SPIR-V generation failed: " + messages_text);
    return result;
  }

  result.ok = true;
  return result;
}

std::string finalize_spirv(std::vector<uint32_t>& spirv, const CompileOptions& options) {
  const spv_target_env env = target_env(options.vulkan_version);
  std::string messages;
  auto consumer = [&](spv_message_level_t, const char*, const spv_position_t& pos, const char* message) {
    messages += "word " + std::to_string(pos.index) + ": " + message + "\n";
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

std::string disassemble_spirv(const std::vector<uint32_t>& spirv, const CompileOptions& options) {
  spvtools::SpirvTools tools(target_env(options.vulkan_version));
  std::string text;
  tools.Disassemble(spirv, &text,
                    SPV_BINARY_TO_TEXT_OPTION_FRIENDLY_NAMES | SPV_BINARY_TO_TEXT_OPTION_INDENT);
  return text;
}

}  // namespace statepack::packager
