#include "hlsl_system_values.hpp"

#include <cctype>

#include "glslang_tree.hpp"

namespace statepack::packager {
namespace {

bool starts_with_ignoring_case(const char* text, const char* prefix) {
  for (; *prefix; ++text, ++prefix)
    if (std::toupper(static_cast<unsigned char>(*text)) != *prefix) return false;
  return true;
}

// A varying's qualifier that carries an SV_ semantic glslang left without a built-in.
bool unknown_system_value(const glslang::TQualifier& q) {
  return q.semanticName && q.builtIn == glslang::EbvNone &&
         starts_with_ignoring_case(q.semanticName, "SV_") &&
         !starts_with_ignoring_case(q.semanticName, "SV_TARGET");
}

}  // namespace

std::vector<UnknownSystemValue> find_unknown_system_values(const glslang::TShader& shader) {
  std::vector<UnknownSystemValue> found;
  for_each_global(shader, [&](const glslang::TIntermSymbol& symbol) {
    const glslang::TType& type = symbol.getType();
    const glslang::TStorageQualifier storage = type.getQualifier().storage;
    if (storage != glslang::EvqVaryingIn && storage != glslang::EvqVaryingOut) return;
    const bool output = storage == glslang::EvqVaryingOut;
    if (unknown_system_value(type.getQualifier()))
      found.push_back({symbol.getLoc().getFilenameStr(), symbol.getLoc().line, symbol.getName().c_str(),
                       type.getQualifier().semanticName, output});
    if (type.isStruct())
      for (const glslang::TTypeLoc& member : *type.getStruct())
        if (unknown_system_value(member.type->getQualifier()))
          found.push_back({member.loc.getFilenameStr(), member.loc.line, member.type->getFieldName().c_str(),
                           member.type->getQualifier().semanticName, output});
  });
  return found;
}

}  // namespace statepack::packager
