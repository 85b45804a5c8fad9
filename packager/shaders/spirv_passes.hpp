// The SPIRV-Tools passes statepack runs on a module between the compiler and the layout: HLSL
// legalization, unused globals, and the cut of a module to one entry point. Each returns "" or why it
// failed.
#pragma once

#include <spirv-tools/libspirv.h>

#include <cstdint>
#include <string>
#include <vector>

#include "hlsl_vertex_inputs.hpp"

namespace statepack::packager {

struct CompileOptions;

// The SPIRV-Tools environment of the target: --vulkan_version's, or OpenGL 4.5.
spv_target_env target_env(const CompileOptions& options);

// The highest SPIR-V version (0x00010000 | minor << 8) the target takes: 1.0 for Vulkan 1.0 and OpenGL,
// 1.3 for Vulkan 1.1, 1.5 for 1.2, 1.6 for 1.3.
uint32_t max_spirv_version(const CompileOptions& options);

// What glslang's HLSL front end makes is not valid Vulkan SPIR-V until it is legalized (opaque values
// copied through locals, dead members of entry-point structs). glslang and Diligent always legalize
// HLSL, whatever the optimisation level, and so does statepack; then a vertex shader's ATTRIBn inputs
// move to location n (`semantics`: every input's semantic) and the semantic decorations are stripped.
std::string legalize_hlsl(std::vector<uint32_t>& spirv, const CompileOptions& options, bool vertex,
                          std::vector<VertexInputSemantic>& semantics);

// The same for a module of another compiler (BYTECODE): legalized when `hlsl`, its ATTRIBn inputs placed
// when it carries semantic decorations, and stripped of reflection decorations and extensions no driver
// needs (SPV_GOOGLE_hlsl_functionality1, SPV_GOOGLE_user_type).
std::string prepare_module(std::vector<uint32_t>& spirv, const CompileOptions& options, bool hlsl,
                           bool vertex, std::vector<VertexInputSemantic>& semantics);

// Removes the functions no entry point calls (after other entry points were cut from a module).
std::string keep_entry_point(std::vector<uint32_t>& spirv, const CompileOptions& options);

// Removes the module-scope variables nothing references: a resource belongs to a shader when its entry
// point statically uses it.
std::string remove_unused_globals(std::vector<uint32_t>& spirv, const CompileOptions& options);

}  // namespace statepack::packager
