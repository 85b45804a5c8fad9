// The environment Diligent Engine compiles every shader in, rebuilt for statepack: the text glslang
// reads before a shader's first line (definitions, the compiler, backend and stage macros, the compile
// flags' pragmas, GLSLExtensions, the -D macros and the shader's Macros) and the #version of GLSL
// that states none. docs/notation.md ("The shader environment") lists every name.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "notation/notation.hpp"

namespace statepack::packager {

struct CompileOptions;

// Where a stretch of the preamble comes from: glslang reports an error in it at its source string -1,
// a place no user can find; the message names this instead. Only the kind and index are kept: the name
// and the notation's location are the shader's and the options' (read when an error needs them, not on
// every compile and cache key).
struct PreambleSource {
  enum class Kind { environment, glsl_extensions, global_macro, macro };
  size_t begin = 0;  // the stretch's first byte in the preamble
  Kind kind = Kind::environment;
  size_t index = 0;  // of the -D macro (CompileOptions::global_macros) or of the Macros entry
};

struct ShaderEnvironment {
  std::string preamble;
  std::vector<PreambleSource> sources;  // by `begin`, the first at 0
  // How much of the preamble is statepack's own text (the definitions and macros before the -D macros
  // and the shader's Macros): a fixed cost, left out of the compile's allocation budget.
  size_t fixed_bytes = 0;
  // The #version a GLSL source without one is compiled as: GLSLVersion, else 460 (Diligent's Vulkan
  // maximum, "#version 460 core"). A source's own #version wins (statepack also takes such files).
  int default_glsl_version = 460;
};

// Puts `line` (ending in a newline) before the preamble, from the environment.
void prepend_to_preamble(ShaderEnvironment& environment, std::string_view line);

// What wrote line `line` (1-based, as glslang counts) of the preamble; nullptr past its end.
const PreambleSource* preamble_source(const ShaderEnvironment& environment, int line);

// The environment of `shader` compiled with `options` (for Vulkan, or for OpenGL with options.opengl).
ShaderEnvironment shader_environment(const ShaderDesc& shader, const CompileOptions& options);

// Diligent's stage macros of a Vulkan stage (VERTEX_SHADER; PIXEL_SHADER and FRAGMENT_SHADER; ...).
std::vector<std::string_view> stage_macros(uint32_t stage);

// The names the environment defines for `shader` (for messages: "statepack defines X as Diligent does").
bool environment_defines(const ShaderDesc& shader, const CompileOptions& options, std::string_view name);

// `text` with GL_ARB_shading_language_include (which Diligent's GLSL enables for #include) spelt
// GL_GOOGLE_include_directive, the name under which glslang (Debian 12's 12.0) knows #include.
std::string with_include_directive(std::string_view text);

// The HLSL definitions file (packager/shaders/environment/diligent_hlsl.fxh), as compiled in.
std::string_view diligent_hlsl_definitions();

}  // namespace statepack::packager
