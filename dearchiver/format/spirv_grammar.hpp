// SPIR-V's grammar as tables: each instruction's operands, and the enumerants that carry operands of
// their own (a decoration's literals, an image operand's ids). The rows are generated at build time from
// spirv-headers' spirv.core.grammar.json (spirv_grammar_gen.cpp); this header gives them their types.
#pragma once

#include <cstdint>

namespace statepack::spirv::grammar {

enum class Kind : uint8_t {
  result_type,      // <id> of the result's type
  result,           // <id> the instruction defines
  id,               // <id> of something defined elsewhere (IdRef, IdScope, IdMemorySemantics)
  literal,          // one word
  string,           // nul-terminated UTF-8, padded to a word
  context_number,   // a constant's value: as many words as its type's width needs
  spec_opcode,      // OpSpecConstantOp's opcode; that opcode's operands follow
  pair_literal_id,  // OpSwitch target: a literal as wide as the selector, then a label <id>
  pair_id_literal,
  pair_id_id,
  value_enum,  // one word; some values carry operands (kEnumerants)
  bit_enum,    // one word of bits; each set bit carrying operands adds them, lowest bit first
};
enum class Quantifier : uint8_t { one, optional, many };

struct Operand {
  Kind kind;
  Quantifier quantifier;
  bool names_type;    // a type declaration's operand that must name a type (element, member, pointee ...)
  uint8_t enum_kind;  // index into kEnumKinds for value_enum and bit_enum
};
struct Enumerant {
  uint32_t value;
  uint16_t first_operand, operand_count;  // its parameters, in kOperands
};
struct EnumKind {
  bool bits;
  uint16_t first_enumerant, enumerant_count;  // only those with parameters, sorted by value
};

enum InstructionFlags : uint8_t {
  kDefinesType = 1,          // an OpType* with a result
  kDefinesConstant = 2,      // constant creation (OpConstant, OpSpecConstant*, ...)
  kMayReferenceForward = 4,  // debug, annotation and mode-setting instructions precede what they name
};
struct Instruction {
  uint16_t opcode;
  uint16_t first_operand;
  uint8_t operand_count;
  uint8_t flags;
  uint16_t name;  // offset of its name ("OpTypeInt") in kInstructionNames: a table without pointers
};

#include "spirv_grammar_table.inc"

// Its name, or "" for the instructions the table leaves unnamed (spirv_grammar_gen.py says which).
inline const char* name_of(const Instruction& instruction) {
  return kInstructionNames + instruction.name;
}

}  // namespace statepack::spirv::grammar
