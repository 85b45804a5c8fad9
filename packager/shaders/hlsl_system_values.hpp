// HLSL system values glslang does not know (SV_ViewID, SV_ShadingRate, ...). glslang turns a semantic it
// does not map to a SPIR-V built-in into an ordinary input or output with a location, so the shader
// would ask an InputLayout or an earlier stage for a value only the device provides. Found here, in
// glslang's parse tree, so the shader is refused at the declaration, naming the semantic.
#pragma once

#include <string>
#include <vector>

namespace glslang {
class TShader;
}

namespace statepack::packager {

struct UnknownSystemValue {
  std::string file;  // as glslang names it: the shader's display name or the #include's
  int line = 0;
  std::string variable;
  std::string semantic;  // as written: "SV_ViewID"
  bool output = false;
};

// Pipeline inputs and outputs of a parsed HLSL shader whose semantic begins with SV_ but that glslang
// made ordinary varyings. SV_Target (a fragment output with a location by design) is not one of them.
std::vector<UnknownSystemValue> find_unknown_system_values(const glslang::TShader& shader);

}  // namespace statepack::packager
