#include "glslang_tree.hpp"

namespace statepack::packager {

void for_each_global(const glslang::TShader& shader,
                     const std::function<void(const glslang::TIntermSymbol&)>& visit) {
  const glslang::TIntermediate* intermediate = shader.getIntermediate();
  if (!intermediate || !intermediate->getTreeRoot()) return;
  const glslang::TIntermAggregate* root = intermediate->getTreeRoot()->getAsAggregate();
  if (!root) return;
  for (const TIntermNode* node : root->getSequence()) {
    const glslang::TIntermAggregate* objects = node->getAsAggregate();
    if (!objects || objects->getOp() != glslang::EOpLinkerObjects) continue;
    for (const TIntermNode* object : objects->getSequence())
      if (const glslang::TIntermSymbol* symbol = object->getAsSymbolNode()) visit(*symbol);
  }
}

}  // namespace statepack::packager
