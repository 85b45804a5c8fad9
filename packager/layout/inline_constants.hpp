// Diligent's inline constants (a CONSTANT_BUFFER flagged INLINE_CONSTANTS, ArraySize 32-bit values) as
// Vulkan push constants. Vulkan gives a stage one push-constant block, so, as in Diligent's Vulkan
// backend, one inline-constant resource per pipeline is pushed: the first of the lowest-BindingIndex
// signature that has one (in VarType order: STATIC, MUTABLE, DYNAMIC, then as listed), or, without
// signatures, the first ResourceLayout variable flagged INLINE_CONSTANTS. Its range is offset 0, its
// values x 4 bytes; each shader's uniform block of that name becomes the push-constant block
// (push_constant_conversion.hpp). Any other inline-constant resource stays a uniform buffer the
// application binds (Diligent fills such a buffer itself), with a warning.
#pragma once

#include <string>
#include <vector>

#include "notation/diagnostics.hpp"
#include "notation/notation.hpp"
#include "pipeline_layout.hpp"

namespace statepack::packager {

struct InlineConstants {
  std::string name;     // the resource pushed; empty: none
  uint32_t values = 0;  // its ArraySize; 0: sized by the shaders' block (a ResourceLayout variable)
  uint32_t stages = 0;  // its ShaderStages; 0: every stage whose shader uses it
  Location where;       // the resource or variable, for messages
  std::vector<std::string> others;  // the pipeline's other inline-constant resources
};

// The inline constants `pipeline` pushes, from its signatures or ResourceLayout variables.
InlineConstants pushed_inline_constants(const PipelineDesc& pipeline, const Notation& notation);

// Turns each stage's uniform block `pushed.name` into its push-constant block in out.patched_spirv (the
// last change made to those modules) and sets out's push-constant range. False, with an error naming the
// pipeline, the shader and the resource, when a stage cannot take it.
bool push_inline_constants(const PipelineDesc& pipeline, const InlineConstants& pushed,
                           const std::vector<StageInput>& stages, PipelineLayout& out, Diagnostics& diag);

}  // namespace statepack::packager
