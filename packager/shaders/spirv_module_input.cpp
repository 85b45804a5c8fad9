#include "spirv_module_input.hpp"

#include <spirv/unified1/spirv.h>
#include <vulkan/vulkan_core.h>
#include <spirv-tools/libspirv.hpp>

#include <cstring>
#include <set>

#include "shader_compiler.hpp"
#include "spirv_passes.hpp"

namespace statepack::packager {
namespace {

constexpr size_t kHeaderWords = 5;

uint32_t execution_model_of(uint32_t stage) {
  switch (stage) {
    case VK_SHADER_STAGE_VERTEX_BIT:
      return SpvExecutionModelVertex;
    case VK_SHADER_STAGE_TESSELLATION_CONTROL_BIT:
      return SpvExecutionModelTessellationControl;
    case VK_SHADER_STAGE_TESSELLATION_EVALUATION_BIT:
      return SpvExecutionModelTessellationEvaluation;
    case VK_SHADER_STAGE_GEOMETRY_BIT:
      return SpvExecutionModelGeometry;
    case VK_SHADER_STAGE_FRAGMENT_BIT:
      return SpvExecutionModelFragment;
    default:
      return SpvExecutionModelGLCompute;
  }
}

const char* model_name(uint32_t model) {
  switch (model) {
    case SpvExecutionModelVertex:
      return "vertex";
    case SpvExecutionModelTessellationControl:
      return "hull";
    case SpvExecutionModelTessellationEvaluation:
      return "domain";
    case SpvExecutionModelGeometry:
      return "geometry";
    case SpvExecutionModelFragment:
      return "pixel";
    case SpvExecutionModelGLCompute:
      return "compute";
    default:
      return "other";
  }
}

std::string version_text(uint32_t version) {
  return std::to_string(version >> 16 & 0xFF) + "." + std::to_string(version >> 8 & 0xFF);
}

std::string literal_string(const std::vector<uint32_t>& words, size_t first, size_t end) {
  std::string out;
  for (size_t w = first; w < end; ++w)
    for (int b = 0; b < 4; ++b) {
      const char c = char(words[w] >> (8 * b) & 0xFF);
      if (c == 0) return out;
      out += c;
    }
  return out;
}

struct EntryPoint {
  size_t at;  // its OpEntryPoint
  uint32_t model, function;
  std::string name;
};

// The module's header and whether the target takes it.
std::string check_header(std::string_view bytes, const CompileOptions& options,
                         std::vector<uint32_t>& words) {
  if (bytes.size() % 4 != 0)
    return "is " + std::to_string(bytes.size()) +
           " bytes, not a whole number of 32-bit words: not a SPIR-V binary";
  if (bytes.size() < kHeaderWords * 4)
    return "is too small to be a SPIR-V module (" + std::to_string(bytes.size()) + " bytes)";
  words.resize(bytes.size() / 4);
  std::memcpy(words.data(), bytes.data(), bytes.size());
  if (words[0] == 0x03022307u) return "is big-endian SPIR-V; Vulkan takes modules in little-endian words";
  if (words[0] != SpvMagicNumber)
    return "does not start with SPIR-V's magic number 0x07230203: is it a SPIR-V binary (BYTECODE)?";
  if (words[1] > max_spirv_version(options))
    return "is SPIR-V " + version_text(words[1]) + ", but " +
           (options.opengl ? std::string("OpenGL 4.5 (GL_ARB_gl_spirv)")
                           : "--vulkan_version 1." + std::to_string(options.vulkan_version >> 12 & 0x3FF)) +
           " takes SPIR-V " + version_text(max_spirv_version(options)) +
           " at most: pack for a later Vulkan version, or build the module for an earlier SPIR-V";
  return "";
}

// Keeps the entry point the shader uses and cuts the others (with their execution modes).
std::string choose_entry_point(std::vector<uint32_t>& words, const ShaderDesc& shader, bool& from_hlsl,
                               std::string& chosen) {
  std::vector<EntryPoint> entries;
  for (size_t at = kHeaderWords; at < words.size();) {
    const uint32_t op = words[at] & 0xFFFFu, n = words[at] >> 16;
    if (n == 0 || at + n > words.size()) return "is malformed (an instruction runs past its end)";
    if (op == SpvOpEntryPoint && n >= 4)
      entries.push_back({at, words[at + 1], words[at + 2], literal_string(words, at + 3, at + n)});
    if (op == SpvOpSource && n >= 2) from_hlsl = from_hlsl || words[at + 1] == SpvSourceLanguageHLSL;
    at += n;
  }
  const uint32_t model = execution_model_of(shader.stage);
  const EntryPoint* keep = nullptr;
  for (const EntryPoint& e : entries)
    if (e.model == model && e.name == shader.entry_point) keep = &e;
  for (const EntryPoint& e : entries)
    if (!keep && e.model == model) keep = &e;
  if (!keep) {
    std::string have;
    for (const EntryPoint& e : entries)
      have += (have.empty() ? "" : ", ") + ("'" + e.name + "' (" + model_name(e.model) + ")");
    return "has no " + std::string(model_name(model)) + " shader entry point (it has " +
           (have.empty() ? "none" : have) + ")";
  }
  chosen = keep->name;
  const uint32_t function = keep->function;
  std::set<size_t> cut;
  for (const EntryPoint& e : entries)
    if (&e != keep) cut.insert(e.at);
  std::vector<uint32_t> out(words.begin(), words.begin() + kHeaderWords);
  for (size_t at = kHeaderWords; at < words.size();) {
    const uint32_t op = words[at] & 0xFFFFu, n = words[at] >> 16;
    const bool other_mode =
        (op == SpvOpExecutionMode || op == SpvOpExecutionModeId) && n >= 2 && words[at + 1] != function;
    if (!cut.count(at) && !other_mode)
      out.insert(out.end(), words.begin() + std::ptrdiff_t(at), words.begin() + std::ptrdiff_t(at + n));
    at += n;
  }
  words = std::move(out);
  return "";
}

}  // namespace

std::string take_spirv_module(std::string_view bytes, const ShaderDesc& shader, const CompileOptions& options,
                              SpirvModuleInput& out) {
  if (std::string problem = check_header(bytes, options, out.words); !problem.empty()) return problem;
  std::string messages;
  spvtools::SpirvTools tools(target_env(options));
  tools.SetMessageConsumer([&](spv_message_level_t, const char*, const spv_position_t&, const char* m) {
    if (messages.empty()) messages = m;
  });
  if (!tools.Validate(out.words)) {
    for (char& c : messages)
      if (c == '\n') c = ' ';
    return "is not valid SPIR-V for " +
           (options.opengl ? std::string("OpenGL 4.5")
                           : "Vulkan 1." + std::to_string(options.vulkan_version >> 12 & 0x3FF)) +
           ": " + messages;
  }
  bool from_hlsl = false;
  if (std::string problem = choose_entry_point(out.words, shader, from_hlsl, out.entry_point);
      !problem.empty())
    return problem;
  if (std::string problem = keep_entry_point(out.words, options); !problem.empty()) return problem;
  return prepare_module(out.words, options, from_hlsl, shader.stage == VK_SHADER_STAGE_VERTEX_BIT,
                        out.semantics);
}

}  // namespace statepack::packager
