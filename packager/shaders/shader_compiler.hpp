// GLSL and HLSL to SPIR-V with glslang, in process; each result validated by SPIRV-Tools.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "digest.hpp"
#include "hlsl_vertex_inputs.hpp"
#include "notation/diagnostics.hpp"
#include "notation/input_file.hpp"
#include "notation/notation.hpp"
#include "shader_messages.hpp"

namespace statepack::packager {

enum class Optimization { none, speed, size };

struct CompileOptions {
  std::vector<std::filesystem::path> include_dirs;                 // -s: searched after the includer's dir
  std::vector<std::pair<std::string, std::string>> global_macros;  // -D NAME=VALUE
  uint32_t vulkan_version = 0x00400000;                            // VK_API_VERSION_1_0: SPIR-V 1.0
  Optimization optimization = Optimization::none;
  bool strip_debug_info = false;  // OpName, OpLine, ...: names the archive keeps in its binding table
  // Compile for OpenGL 4.5 with GL_ARB_gl_spirv instead (glslang's OpenGL client, SPIR-V 1.0, validated
  // for OpenGL 4.5): GL_SPIRV is defined and VULKAN is not. Used for GLSL that tests those macros;
  // every other shader reaches OpenGL translated from its Vulkan SPIR-V (gl_translate.hpp).
  bool opengl = false;
  // Diligent's shader environment (shader_environment.hpp): its definitions and its compiler, backend
  // and stage macros. Off (--shader-environment none): only the -D macros, the shader's Macros and the
  // compile flags' effects.
  bool shader_environment = true;
  // --max-input-size: each shader file and #include at most this, and a shader's includes in all.
  uint64_t max_input_bytes = kMaxInputBytes;
  // --no-compile: a shader the compile cache does not have is an error instead of a compile (the
  // archive assembled from what other machines compiled). Decides no result: in no cache key.
  bool no_compile = false;
};

// An #include glslang asked for while compiling, as the compile cache replays it (compile_cache.hpp).
struct IncludeRecord {
  std::string header;    // as written: #include "header" (local) or <header>
  std::string includer;  // glslang's name for the including file (where a local include is looked for first)
  bool local = true;
  std::string path;  // where it was found
  Digest text_hash{};
};

struct CompiledShader {
  std::vector<uint32_t> spirv;
  Digest source_hash{};                 // of the text glslang compiled (the shader's file or Source)
  std::vector<IncludeRecord> includes;  // in the order glslang asked for them
  std::vector<InputFile> files_read;    // the source and every #include, for the depfile and output checks
  bool backend_specific = false;        // GLSL whose text (or an #include's) tests_backend_macros
  // HLSL textures and samplers declared [[vk::combinedImageSampler]] (hlsl_combined_image_samplers.hpp)
  std::vector<std::string> combined_image_samplers;
  // An HLSL vertex shader's inputs and their semantics (ATTRIBn already placed at location n), for an
  // InputLayout that names another HLSLSemantic.
  std::vector<VertexInputSemantic> vertex_semantics;
  std::string entry_point;  // the module's: EntryPoint, or the one a BYTECODE module was cut to
  bool ok = false;
};

// Two slots compile to the same module when everything that feeds glslang is equal: that, as one string
// (a pack compiles each distinct one once).
std::string unit_key(const ShaderDesc& shader);

// Builds glslang's built-in symbol tables for what compiling `shader` needs (its language, #version and
// target), as its compile would: glslang builds them once per process, for every stage at once (~50 ms,
// serial under a lock of glslang's). A pack calls it on another core while it reads and hashes, for a
// shader it will likely compile; whatever it cannot read or parse is left to that compile to report.
void prepare_compiler(const ShaderDesc& shader, const CompileOptions& options);
// What of `shader`'s text picks those tables: its #version line (read from its file), "" for HLSL, for
// a text without one, or for a file that cannot be read.
std::string tables_version_line(const ShaderDesc& shader, const CompileOptions& options);

// Compiles one shader. Errors are reported against the shader's own file and line (or the #include's);
// `messages` collects them from every shader, so an error in a shared #include is reported once.
CompiledShader compile_shader(const ShaderDesc& shader, const CompileOptions& options,
                              ShaderMessages& messages);
// The same for a single shader, its errors added to `diagnostics` at once.
CompiledShader compile_shader(const ShaderDesc& shader, const CompileOptions& options,
                              Diagnostics& diagnostics);

// Compiles GLSL that statepack itself generated (the OpenGL translation, gl_translate.hpp) with glslang's
// OpenGL client: no includes, no macros. Empty SPIR-V, with glslang's log in `log`, when it fails.
std::vector<uint32_t> compile_generated_glsl(const std::string& glsl, uint32_t stage, std::string& log);

// Whether a GLSL source or one of its #includes tests VULKAN or GL_SPIRV in a preprocessor directive
// (#if, #ifdef, #ifndef, #elif): its author wrote code per backend, so the OpenGL backend compiles its
// own text rather than translating its Vulkan SPIR-V.
bool tests_backend_macros(std::string_view source);

// Where `#include header` from the file glslang calls `includer` is found: next to it (local includes
// only), then in the -s directories; empty when nowhere.
std::filesystem::path resolve_include(const std::string& header, const std::string& includer, bool local,
                                      const std::vector<std::filesystem::path>& include_dirs);

// SHA-256 of text, as IncludeRecord and the compile cache keep it.
Digest text_hash(std::string_view text);

// Optimises and strips `spirv` as the options say, then validates it with SPIRV-Tools.
// Returns an empty string on success, else the reason.
std::string finalize_spirv(std::vector<uint32_t>& spirv, const CompileOptions& options);
// Only the validation finalize_spirv ends with (a finalised module from a shared cache).
std::string validate_spirv(const std::vector<uint32_t>& spirv, const CompileOptions& options);

// SPIR-V assembly text of `spirv`, for --dump_dir.
std::string disassemble_spirv(const std::vector<uint32_t>& spirv, const CompileOptions& options);

}  // namespace statepack::packager
