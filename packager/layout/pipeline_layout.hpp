// A pipeline's resource layout: from its resource signatures (set = BindingIndex, binding = the
// resource's position) or, without signatures, from SPIR-V reflection merged across stages. The
// shaders' DescriptorSet/Binding decorations are then patched to match, so the archive's SPIR-V and
// layout agree exactly and nothing is patched at run time.
#pragma once

#include <vector>

#include "contents_builder.hpp"
#include "format/spirv_walk.hpp"
#include "notation/diagnostics.hpp"
#include "notation/notation.hpp"
#include "shaders/hlsl_vertex_inputs.hpp"
#include "shaders/spirv_reflect.hpp"

namespace statepack::packager {

struct StageInput {
  const ShaderDesc* desc;
  const std::vector<uint32_t>* spirv;
  const Reflection* reflection;
  const spirv::Module* module = nullptr;  // `spirv` walked (on the compile's threads), when it could be
  // An HLSL vertex shader's inputs and their semantics (hlsl_vertex_inputs.hpp); null for the others.
  const std::vector<VertexInputSemantic>* semantics = nullptr;
  // The module's entry point: the shader's EntryPoint, or the one a BYTECODE module was cut to.
  std::string_view entry_point;
};

struct PipelineLayout {
  std::vector<uint32_t> set_layouts;  // per set number: index in the archive's set layouts, or kNone
  uint32_t push_constant_size = 0;
  uint32_t push_constant_stages = 0;
  std::vector<std::vector<uint32_t>> patched_spirv;  // per stage, in the order given
};

// The set layout a signature becomes (stored named, unless it is in Ignore.Signatures).
format::SetLayout signature_set_layout(const SignatureDesc& signature, bool named, ContentsBuilder& builder);

struct LayoutOptions {
  // --strict: ResourceLayout variables and immutable samplers that name nothing the shaders use are
  // errors instead of Diligent's warnings.
  bool strict = false;
};

// Builds the layout of `pipeline` and patches its stages; false (with diagnostics) on any mismatch.
bool build_pipeline_layout(const PipelineDesc& pipeline, const std::vector<StageInput>& stages,
                           const Notation& notation, ContentsBuilder& builder, const LayoutOptions& options,
                           PipelineLayout& out, Diagnostics& diag);

}  // namespace statepack::packager
