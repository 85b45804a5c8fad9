#include "hlsl_push_constants.hpp"

// glslang's parse tree: its public headers expose TShader only, the tree is in the internal ones that
// Debian installs too. Same defines as shader_compiler.cpp, so the class layouts match the library's.
#define ENABLE_HLSL 1
#include <glslang/MachineIndependent/localintermediate.h>
#include <glslang/Public/ShaderLang.h>

namespace statepack::packager {

std::vector<MisplacedPushConstant> find_misplaced_push_constants(const glslang::TShader& shader) {
  std::vector<MisplacedPushConstant> found;
  const glslang::TIntermediate* intermediate = shader.getIntermediate();
  if (!intermediate || !intermediate->getTreeRoot()) return found;
  const glslang::TIntermAggregate* root = intermediate->getTreeRoot()->getAsAggregate();
  if (!root) return found;
  // Every global is listed in the tree's linker objects, used or not. glslang keeps the attribute on
  // the member it made of the variable, which is how the uniform block gives it away.
  for (const TIntermNode* node : root->getSequence()) {
    const glslang::TIntermAggregate* objects = node->getAsAggregate();
    if (!objects || objects->getOp() != glslang::EOpLinkerObjects) continue;
    for (const TIntermNode* object : objects->getSequence()) {
      const glslang::TIntermSymbol* symbol = object->getAsSymbolNode();
      if (!symbol) continue;
      const glslang::TType& type = symbol->getType();
      if (type.getQualifier().storage != glslang::EvqUniform || type.getBasicType() != glslang::EbtBlock ||
          type.getQualifier().layoutPushConstant)
        continue;
      for (const glslang::TTypeLoc& member : *type.getStruct()) {
        if (!member.type->getQualifier().layoutPushConstant) continue;
        found.push_back({member.loc.getFilenameStr(), member.loc.line, member.type->getFieldName().c_str(),
                         member.type->isStruct() ? member.type->getTypeName().c_str() : ""});
      }
    }
  }
  return found;
}

}  // namespace statepack::packager
