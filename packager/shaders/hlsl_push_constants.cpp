#include "hlsl_push_constants.hpp"

#include "glslang_tree.hpp"

namespace statepack::packager {

std::vector<MisplacedPushConstant> find_misplaced_push_constants(const glslang::TShader& shader) {
  std::vector<MisplacedPushConstant> found;
  // glslang keeps the attribute on the member it made of the variable, which is how the uniform block
  // gives it away.
  for_each_global(shader, [&](const glslang::TIntermSymbol& symbol) {
    const glslang::TType& type = symbol.getType();
    if (type.getQualifier().storage != glslang::EvqUniform || type.getBasicType() != glslang::EbtBlock ||
        type.getQualifier().layoutPushConstant)
      return;
    for (const glslang::TTypeLoc& member : *type.getStruct()) {
      if (!member.type->getQualifier().layoutPushConstant) continue;
      found.push_back({member.loc.getFilenameStr(), member.loc.line, member.type->getFieldName().c_str(),
                       member.type->isStruct() ? member.type->getTypeName().c_str() : ""});
    }
  });
  return found;
}

}  // namespace statepack::packager
