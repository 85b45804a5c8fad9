// BYTECODE shaders: a SPIR-V module another compiler made (DXC, Slang, an older glslang), read from the
// shader's FilePath and then treated like a compiled source: validated for the target, cut to the
// shader's entry point, legalized when it comes from HLSL, its ATTRIBn vertex inputs placed, reflected,
// and remapped to the pipeline's layout by the same steps.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "hlsl_vertex_inputs.hpp"
#include "notation/notation.hpp"

namespace statepack::packager {

struct CompileOptions;

struct SpirvModuleInput {
  std::vector<uint32_t> words;
  std::string entry_point;  // the one kept
  std::vector<VertexInputSemantic> semantics;
};

// Takes the file's `bytes` as the module of `shader`. The entry point is the shader's EntryPoint when the
// module has it for the shader's stage, else (as in Diligent, which ignores EntryPoint for bytecode) the
// module's first entry point of that stage. Returns "" or what is wrong, in the user's words.
std::string take_spirv_module(std::string_view bytes, const ShaderDesc& shader, const CompileOptions& options,
                              SpirvModuleInput& out);

}  // namespace statepack::packager
