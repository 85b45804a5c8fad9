// GLSL and HLSL to SPIR-V with glslang, in process; each result validated by SPIRV-Tools.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "diagnostics.hpp"
#include "notation.hpp"

namespace statepack::packager {

struct CompileOptions {
  std::vector<std::filesystem::path> include_dirs;                 // -s: searched after the includer's dir
  std::vector<std::pair<std::string, std::string>> global_macros;  // -D NAME=VALUE
  uint32_t vulkan_version = 0x00400000;                            // VK_API_VERSION_1_0: SPIR-V 1.0
};

struct CompiledShader {
  std::vector<uint32_t> spirv;
  std::vector<std::filesystem::path> files_read;  // the source and every #include, for the depfile
  bool ok = false;
};

// Compiles one shader. Errors are reported against the shader's own file and line.
CompiledShader compile_shader(const ShaderDesc& shader, const CompileOptions& options,
                              Diagnostics& diagnostics);

}  // namespace statepack::packager
