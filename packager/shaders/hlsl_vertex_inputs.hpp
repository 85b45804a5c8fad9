// HLSL vertex inputs placed by semantic, as Diligent places them: an input of semantic ATTRIBn (any
// case) reads location n, whatever order the shader declares its inputs in; other semantics keep the
// location glslang gave them (declaration order). The semantics come from glslang's UserSemantic
// decorations (SPV_GOOGLE_hlsl_functionality1), which the compiler strips afterwards: no driver needs
// them. The semantics are kept, so that a pipeline whose InputLayout names another HLSLSemantic can
// place those inputs the way Direct3D matches them (semantic name + InputIndex).
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace statepack::packager {

// A vertex shader's input variable and the semantic the source gave it.
struct VertexInputSemantic {
  uint32_t variable = 0;  // result id of its OpVariable
  std::string semantic;   // as glslang wrote it ("ATTRIB3", "TEXCOORD0")
  bool operator==(const VertexInputSemantic&) const = default;
};

// The semantics of the Input variables of `spirv` (glslang's UserSemantic decorations).
std::vector<VertexInputSemantic> vertex_input_semantics(std::span<const uint32_t> spirv);

// n for a semantic "ATTRIBn" (case-insensitive; "ATTRIB" alone is 0, as in Diligent), else nullopt.
std::optional<uint32_t> attrib_index(std::string_view semantic);

// Whether `semantic` is `name` with index `index` in Direct3D's sense: "TEXCOORD1" is TEXCOORD 1, and
// "TEXCOORD" is TEXCOORD 0 (case-insensitive).
bool semantic_matches(std::string_view semantic, std::string_view name, uint32_t index);

// Sets the Location decoration of `variable` in `spirv`; false when it has none.
bool set_location(std::vector<uint32_t>& spirv, uint32_t variable, uint32_t location);

// Moves every input of semantic ATTRIBn to location n. Returns "" or what stands in the way: two inputs
// that would read one location (named with their semantics).
std::string place_attrib_inputs(std::vector<uint32_t>& spirv, const std::vector<VertexInputSemantic>& inputs);

}  // namespace statepack::packager
