// The structure every consumer of a SPIR-V module relies on, checked before the module reaches the
// validation layer or a driver (both crash on an id that names nothing). Not a validator: it knows each
// instruction's operands from SPIR-V's grammar (spirv_grammar.hpp), not their semantics.
#pragma once

#include <cstdint>
#include <span>

#include "statepack/result.hpp"

namespace statepack::spirv {

// `words` is a whole module whose header walk() has checked (magic, version, bound). Checks that
//  - every instruction is one of SPIR-V's, its operands exactly those its grammar gives it (literal
//    strings nul-terminated, constants as wide as their type, enumerants with the operands they carry);
//  - every result id is below the bound and defined once;
//  - every id operand is defined in the module, and before its use outside function bodies (types,
//    constants, global variables), except where SPIR-V allows forward references: names, decorations,
//    entry points and execution modes, pointers declared by OpTypeForwardPointer, and function bodies;
//  - every result type is a type; a type's element, member, pointee, parameter and return types are
//    types; an array's length is an integer constant; a variable's type is a pointer; a numeric
//    constant's type is an integer or a float; a function's type is a function type.
// The error says what is wrong, at which word and in which instruction.
Result<void> check_structure(std::span<const uint32_t> words);

// The grammar's version, for messages and docs ("1.6 revision 1").
const char* grammar_version();

}  // namespace statepack::spirv
