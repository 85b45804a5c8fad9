// glslang's parse tree, for the checks that see in it what glslang's messages do not say (HLSL push
// constants it made uniforms, system values it made varyings). Its public headers expose TShader only;
// the tree is in the internal ones Debian installs too, included with the library's own defines.
#pragma once

#include <functional>

#define ENABLE_HLSL 1
#include <glslang/MachineIndependent/localintermediate.h>
#include <glslang/Public/ShaderLang.h>

namespace statepack::packager {

// Calls `visit` with every global of a parsed shader (the tree's linker objects list each, used or not).
void for_each_global(const glslang::TShader& shader,
                     const std::function<void(const glslang::TIntermSymbol&)>& visit);

}  // namespace statepack::packager
