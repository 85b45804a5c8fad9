// HLSL vertex inputs matched to InputLayout elements by semantic. The compiler has placed every input
// of semantic ATTRIBn at location n (Diligent's rule, hlsl_vertex_inputs.hpp); an element that names
// another HLSLSemantic feeds the input of that semantic and its InputIndex (TEXCOORD with InputIndex 2
// feeds TEXCOORD2), as Direct3D matches them, so the element's InputIndex becomes that input's
// location in this pipeline's copy of the module. Inputs of other semantics keep glslang's location
// (declaration order), as in Diligent's Vulkan backend, with a warning that says so.
#pragma once

#include <vector>

#include "notation/diagnostics.hpp"
#include "notation/notation.hpp"
#include "pipeline_layout.hpp"

namespace statepack::packager {

// Moves the inputs of `vs` (an HLSL vertex shader: vs.semantics set) that elements of `pipeline`'s
// InputLayout name by semantic, in `spirv` (the pipeline's copy of the module) and in `reflection` (a copy
// of vs.reflection the later checks read). False, with an error, when two inputs would share a location.
bool place_inputs_by_semantic(const PipelineDesc& pipeline, const StageInput& vs,
                              std::vector<uint32_t>& spirv, Reflection& reflection,
                              const SourceTexts& sources, Diagnostics& diag);

}  // namespace statepack::packager
