// HLSL push constants that glslang would silently turn into uniforms. DXC accepts
// `[[vk::push_constant]] S pc;` on a global struct variable; glslang parses it but moves the variable
// into the `$Global` uniform buffer like any other global, so the pipeline would read a descriptor
// the application never binds. Found here, in glslang's parse tree, so the shader can be refused.
#pragma once

#include <string>
#include <vector>

namespace glslang {
class TShader;
}

namespace statepack::packager {

struct MisplacedPushConstant {
  std::string file;  // as glslang names it: the shader's display name or the #include's
  int line = 0;
  std::string variable;
  std::string type;  // the struct's name, for the suggested spelling; empty for a non-struct
};

// Globals of a parsed HLSL shader that carry [[vk::push_constant]] but ended up in `$Global`.
std::vector<MisplacedPushConstant> find_misplaced_push_constants(const glslang::TShader& shader);

}  // namespace statepack::packager
