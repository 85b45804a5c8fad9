#include "shader_environment.hpp"

#include <vulkan/vulkan_core.h>

#include "notation/enum_tables.hpp"
#include "shader_compiler.hpp"

namespace statepack::packager {

std::vector<std::string_view> stage_macros(uint32_t stage) {
  switch (stage) {
    case VK_SHADER_STAGE_VERTEX_BIT:
      return {"VERTEX_SHADER"};
    case VK_SHADER_STAGE_TESSELLATION_CONTROL_BIT:
      return {"TESS_CONTROL_SHADER", "HULL_SHADER"};
    case VK_SHADER_STAGE_TESSELLATION_EVALUATION_BIT:
      return {"TESS_EVALUATION_SHADER", "DOMAIN_SHADER"};
    case VK_SHADER_STAGE_GEOMETRY_BIT:
      return {"GEOMETRY_SHADER"};
    case VK_SHADER_STAGE_FRAGMENT_BIT:
      return {"FRAGMENT_SHADER", "PIXEL_SHADER"};
    case VK_SHADER_STAGE_COMPUTE_BIT:
      return {"COMPUTE_SHADER"};
    default:
      return {};
  }
}

namespace {

void define(std::string& out, std::string_view name, std::string_view value) {
  out += "#define ";
  out += name;
  if (!value.empty()) {
    out += ' ';
    out += value;
  }
  out += '\n';
}

// What Diligent adds to HLSL it compiles with glslang for Vulkan, in its order: the row-major pragma,
// GLSLANG, the definitions file, the stage macros. VULKAN is glslang's own (100) for a Vulkan target,
// which Diligent's "#ifndef VULKAN" leaves as it is.
void hlsl_environment(const ShaderDesc& shader, bool environment, std::string& out) {
  if (shader.compile_flags & kPackMatrixRowMajor) out += "#pragma pack_matrix(row_major)\n";
  if (!environment) return;
  define(out, "GLSLANG", "");
  out += diligent_hlsl_definitions();
  if (!out.ends_with('\n')) out += '\n';
  for (std::string_view macro : stage_macros(shader.stage)) define(out, macro, "1");
}

// What Diligent adds to GLSL right after #version: GLSLExtensions (not with GLSL_VERBATIM).
void glsl_extensions(const ShaderDesc& shader, std::string& out) {
  if (!shader.verbatim && !shader.glsl_extensions.empty()) {
    out += with_include_directive(shader.glsl_extensions);
    if (!out.ends_with('\n')) out += '\n';
  }
}

// Then (unless GLSL_VERBATIM) the desktop, clip-depth and stage macros and std140 as the default block
// layout; GLSLANG on Vulkan (its OpenGL backend hands the text to the driver, which defines none of
// Vulkan's names). Row-major matrices apply on both backends, so that one source means the same
// everywhere.
void glsl_environment(const ShaderDesc& shader, bool environment, bool opengl, std::string& out) {
  if (shader.compile_flags & kPackMatrixRowMajor) out += "layout(row_major) uniform;\n";
  if (!environment) return;
  if (!opengl) define(out, "GLSLANG", "");
  if (shader.verbatim) return;
  define(out, "DESKTOP_GL", "1");
  define(out, "_NDC_ZERO_TO_ONE", "1");  // clip-space depth 0..1: Vulkan, and statepack's OpenGL
  for (std::string_view macro : stage_macros(shader.stage)) define(out, macro, "1");
  out += "layout(std140) uniform;\n";
}

}  // namespace

std::string with_include_directive(std::string_view text) {
  constexpr std::string_view kArb = "GL_ARB_shading_language_include",
                             kGoogle = "GL_GOOGLE_include_directive";
  std::string out(text);
  for (size_t at = out.find(kArb); at != std::string::npos; at = out.find(kArb, at + kGoogle.size()))
    out.replace(at, kArb.size(), kGoogle);
  return out;
}

void prepend_to_preamble(ShaderEnvironment& environment, std::string_view line) {
  environment.preamble.insert(0, line);
  for (PreambleSource& source : environment.sources) source.begin += line.size();
  environment.sources.insert(environment.sources.begin(), PreambleSource{});
}

const PreambleSource* preamble_source(const ShaderEnvironment& environment, int line) {
  if (line < 1) return nullptr;
  size_t at = 0;  // the first byte of line `line`
  for (int i = 1; i < line; ++i) {
    at = environment.preamble.find('\n', at);
    if (at == std::string::npos) return nullptr;
    ++at;
  }
  if (at >= environment.preamble.size()) return nullptr;
  const PreambleSource* found = nullptr;
  for (const PreambleSource& source : environment.sources)
    if (source.begin <= at) found = &source;
  return found;
}

ShaderEnvironment shader_environment(const ShaderDesc& shader, const CompileOptions& options) {
  ShaderEnvironment env;
  using Kind = PreambleSource::Kind;
  auto from = [&](Kind kind, size_t index = 0) { env.sources.push_back({env.preamble.size(), kind, index}); };
  if (shader.language == SourceLanguage::hlsl) {
    from(Kind::environment);
    hlsl_environment(shader, options.shader_environment, env.preamble);
  } else if (shader.language == SourceLanguage::glsl) {
    from(Kind::glsl_extensions);
    glsl_extensions(shader, env.preamble);
    from(Kind::environment);
    glsl_environment(shader, options.shader_environment, options.opengl, env.preamble);
  }
  env.fixed_bytes = env.preamble.size();
  for (size_t i = 0; i < options.global_macros.size(); ++i) {
    from(Kind::global_macro, i);
    define(env.preamble, options.global_macros[i].first, options.global_macros[i].second);
  }
  for (size_t i = 0; i < shader.macros.size(); ++i) {
    from(Kind::macro, i);
    define(env.preamble, shader.macros[i].first, shader.macros[i].second);
  }
  if (shader.glsl_version != 0) env.default_glsl_version = int(shader.glsl_version);
  return env;
}

bool environment_defines(const ShaderDesc& shader, const CompileOptions& options, std::string_view name) {
  ShaderDesc bare = shader;
  bare.macros.clear();
  CompileOptions no_globals = options;
  no_globals.global_macros.clear();
  const std::string preamble = shader_environment(bare, no_globals).preamble;
  for (size_t at = preamble.find("#define "); at != std::string::npos;
       at = preamble.find("#define ", at + 1)) {
    const size_t begin = at + 8;
    size_t end = begin;
    while (end < preamble.size() &&
           (std::isalnum(static_cast<unsigned char>(preamble[end])) || preamble[end] == '_'))
      ++end;
    if (std::string_view(preamble).substr(begin, end - begin) == name) return true;
  }
  return name == "VULKAN" && !options.opengl;  // glslang's own, for a Vulkan target
}

}  // namespace statepack::packager
