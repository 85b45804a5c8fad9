// One pass over the module with the grammar's operand tables: each operand is read by its kind, each
// id operand looked up among the definitions seen so far, and uses that SPIR-V lets come before their
// definition are settled at the end. Work and memory are linear in the module's words; nothing recurses
// on input (enumerant parameters nest one level, fixed by the grammar).
#include "spirv_structure.hpp"

#include "support/failure.hpp"

#include <algorithm>
#include <array>
#include <optional>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "spirv_grammar.hpp"

namespace statepack::spirv {
namespace {

using namespace grammar;

enum : uint16_t {
  kOpExtInstImport = 11,
  kOpExtInst = 12,
  kOpTypeInt = 21,
  kOpTypeFloat = 22,
  kOpTypeArray = 28,
  kOpTypePointer = 32,
  kOpTypeFunction = 33,
  kOpTypeForwardPointer = 39,
  kOpConstant = 43,
  kOpSpecConstant = 50,
  kOpSpecConstantOp = 52,
  kOpFunction = 54,
  kOpFunctionEnd = 56,
  kOpVariable = 59,
  kOpSwitch = 251,
};

const Instruction* search_instruction(uint32_t opcode) {
  const auto* end = std::end(kInstructions);
  const auto* it = std::lower_bound(std::begin(kInstructions), end, opcode,
                                    [](const Instruction& i, uint32_t op) { return i.opcode < op; });
  return it != end && it->opcode == opcode ? it : nullptr;
}

// The grammar row of an opcode: a direct table for the core range every module is made of, a search
// beyond it (extensions' opcodes run to 6000 and more, sparsely).
const Instruction* find_instruction(uint32_t opcode) {
  static constexpr uint32_t kDirect = 1024;
  // Row numbers + 1 (0: no such opcode), not pointers: 2 KiB without a relocation per row.
  static constexpr auto direct = [] {
    std::array<uint16_t, kDirect> table{};
    for (size_t row = 0; row < std::size(kInstructions); ++row)
      if (kInstructions[row].opcode < kDirect) table[kInstructions[row].opcode] = uint16_t(row + 1);
    return table;
  }();
  if (opcode >= kDirect) return search_instruction(opcode);
  return direct[opcode] ? &kInstructions[direct[opcode] - 1] : nullptr;
}

// The parameters `value` of enum kind `kind` carries (none for most values).
std::span<const Operand> parameters_of(uint16_t kind, uint32_t value) {
  const EnumKind& k = kEnumKinds[kind];
  const Enumerant* first = kEnumerants + k.first_enumerant;
  const Enumerant* last = first + k.enumerant_count;
  const Enumerant* it =
      std::lower_bound(first, last, value, [](const Enumerant& e, uint32_t v) { return e.value < v; });
  if (it == last || it->value != value) return {};
  return {kOperands + it->first_operand, it->operand_count};
}

// "OpTypeInt"; "opcode 5633" for an instruction the grammar table keeps unnamed; "instruction" for an
// opcode SPIR-V does not have (the message says which).
std::string instruction_text(uint32_t opcode) {
  const Instruction* i = find_instruction(opcode);
  if (!i) return "instruction";
  return *name_of(*i) ? std::string(name_of(*i)) : "opcode " + std::to_string(opcode);
}

std::string id_text(uint32_t id) {
  return "%" + std::to_string(id);
}

// What is known of a defined id: the instruction that defined it (and its grammar flags), and for a
// value its type, for an integer or float type its width.
struct Definition {
  uint16_t opcode = 0;
  uint8_t flags = 0;
  bool defined = false;
  uint32_t info = 0;
};

// Definitions by id: a flat table for the usual dense ids, a hash map when the header's bound is far
// above what the module's words could define (a hostile header must not cost a 4-million-entry table).
class Definitions {
 public:
  Definitions(uint32_t bound, size_t words) {
    if (bound <= 4 * words + 64) flat_.resize(bound);
  }
  const Definition* find(uint32_t id) const {
    if (!flat_.empty()) return flat_[id].defined ? &flat_[id] : nullptr;
    auto it = sparse_.find(id);
    return it == sparse_.end() ? nullptr : &it->second;
  }
  Definition& at(uint32_t id) { return flat_.empty() ? sparse_[id] : flat_[id]; }

 private:
  std::vector<Definition> flat_;
  std::unordered_map<uint32_t, Definition> sparse_;
};

// Each check returns false once the module is found wrong, with the reason in `error` (a Result per
// operand would cost more than the check itself: this runs on every word of every module loaded).
struct Checker {
  std::span<const uint32_t> words;
  uint32_t bound;
  Definitions definitions;
  std::unordered_set<uint32_t> forward_pointers;  // declared by OpTypeForwardPointer
  std::unordered_set<uint32_t> glsl_std_450;      // OpExtInstImport "GLSL.std.450" results
  struct LaterUse {
    uint32_t id;
    size_t at;
  };
  std::vector<LaterUse> later;  // uses SPIR-V lets precede their definition, settled at the end
  bool in_function = false;
  std::optional<Error> error;

  // The instruction being read.
  size_t at = 0;
  const Instruction* instruction = nullptr;
  std::span<const uint32_t> operands;
  size_t pos = 0;
  uint32_t result = 0, result_type = 0;
  std::vector<uint32_t> ids;  // its id operands, in order, for the kind checks

  Checker(std::span<const uint32_t> w) : words(w), bound(w[3]), definitions(w[3], w.size()) {}

  [[gnu::cold]] bool fail(size_t word, const std::string& what) {
    error = detail::failure(ErrorCode::corrupt, "SPIR-V " + instruction_text(words[word] & 0xFFFFu) +
                                                    " at word " + std::to_string(word) + ": " + what);
    return false;
  }
  [[gnu::cold]] bool fail(const std::string& what) { return fail(at, what); }

  const Definition* definition(uint32_t id) const { return id < bound ? definitions.find(id) : nullptr; }
  uint16_t opcode_of(uint32_t id) const {
    const Definition* d = definition(id);
    return d ? d->opcode : 0;
  }
  bool is_type(uint32_t id) const {
    const Definition* d = definition(id);
    return d && (d->flags & kDefinesType);
  }

  bool word(uint32_t& out) {
    if (pos >= operands.size()) return fail("has fewer operands than its grammar requires");
    out = operands[pos++];
    return true;
  }

  bool use(uint32_t id, bool names_type) {
    if (id == 0 || id >= bound)
      return fail("operand " + id_text(id) + " is outside the module's id bound " + std::to_string(bound));
    ids.push_back(id);
    if (const Definition* d = definitions.find(id)) {
      if (names_type && !(d->flags & kDefinesType))
        return fail("type operand " + id_text(id) + " is defined by " + instruction_text(d->opcode) +
                    ", not a type");
      return true;
    }
    if (forward_pointers.count(id) || in_function || (instruction->flags & kMayReferenceForward)) {
      later.push_back({id, at});
      return true;
    }
    return fail((names_type ? "type operand " : "operand ") + id_text(id) +
                " is not defined before its use (outside functions, SPIR-V defines before it uses)");
  }

  // Words a literal of the type `type` takes: its width in words for a numeric type, else 1.
  uint32_t literal_words(uint32_t type) const {
    const Definition* d = definition(type);
    if (!d || (d->opcode != kOpTypeInt && d->opcode != kOpTypeFloat)) return 1;
    return std::max(1u, (d->info + 31) / 32);
  }

  bool operand(const Operand& o) {
    uint32_t w = 0;
    switch (o.kind) {
      case Kind::result_type:
        if (!word(w)) return false;
        if (!is_type(w))
          return fail("result type " + id_text(w) +
                      (definition(w) ? " is not a type" : " is not defined before its use"));
        result_type = w;
        return true;
      case Kind::result:
        if (!word(w)) return false;
        if (w == 0 || w >= bound)
          return fail("result " + id_text(w) + " is outside the module's id bound " + std::to_string(bound));
        if (definitions.find(w)) return fail("result " + id_text(w) + " is defined twice");
        result = w;
        return true;
      case Kind::id:
        return word(w) && use(w, o.names_type);
      case Kind::literal:
        return word(w);
      case Kind::string:
        for (; pos < operands.size(); ++pos)
          if ((operands[pos] & 0xFF000000u) == 0 || (operands[pos] & 0xFF0000u) == 0 ||
              (operands[pos] & 0xFF00u) == 0 || (operands[pos] & 0xFFu) == 0) {
            ++pos;
            return true;
          }
        return fail("has a literal string without its terminating nul");
      case Kind::context_number: {
        // Only OpConstant and OpSpecConstant have one: as wide as their result type.
        const uint32_t n = literal_words(result_type);
        if (operands.size() - pos < n) return fail("has a constant narrower than its type");
        pos += n;
        return true;
      }
      case Kind::spec_opcode: {
        if (!word(w)) return false;
        const Instruction* inner = find_instruction(w);
        if (!inner) return fail("names opcode " + std::to_string(w) + ", which SPIR-V does not have");
        for (const Operand& p : std::span(kOperands + inner->first_operand, inner->operand_count))
          if (p.kind != Kind::result && p.kind != Kind::result_type && !quantified(p)) return false;
        return true;
      }
      case Kind::pair_literal_id: {
        // OpSwitch: the literal is as wide as the selector, its first id operand.
        const uint32_t n = ids.empty() ? 1 : literal_words(definition(ids[0]) ? definition(ids[0])->info : 0);
        if (operands.size() - pos < n) return fail("has a case literal narrower than its selector");
        pos += n;
        return word(w) && use(w, false);
      }
      case Kind::pair_id_literal:
      case Kind::pair_id_id: {
        uint32_t second = 0;
        if (!word(w) || !use(w, false) || !word(second)) return false;
        return o.kind != Kind::pair_id_id || use(second, false);
      }
      case Kind::value_enum:
        return word(w) && parameters(parameters_of(o.enum_kind, w));
      case Kind::bit_enum:
        if (!word(w)) return false;
        for (uint32_t rest = w; rest; rest &= rest - 1)
          if (!parameters(parameters_of(o.enum_kind, rest & (~rest + 1)))) return false;
        return true;
    }
    return fail("has an operand kind this reader does not know");
  }

  bool parameters(std::span<const Operand> list) {
    for (const Operand& p : list)
      if (!quantified(p)) return false;
    return true;
  }

  bool quantified(const Operand& o) {
    if (o.quantifier == Quantifier::one) return operand(o);
    if (o.quantifier == Quantifier::optional) return pos < operands.size() ? operand(o) : true;
    while (pos < operands.size())
      if (!operand(o)) return false;
    return true;
  }

  // The kinds SPIR-V requires of particular operands, beyond "is a type".
  bool kinds() {
    const uint16_t op = instruction->opcode;
    if (op == kOpVariable && opcode_of(result_type) != kOpTypePointer)
      return fail("variable " + id_text(result) + " has type " + id_text(result_type) + ", not a pointer");
    if ((op == kOpConstant || op == kOpSpecConstant) && opcode_of(result_type) != kOpTypeInt &&
        opcode_of(result_type) != kOpTypeFloat)
      return fail("constant " + id_text(result) + " has type " + id_text(result_type) +
                  ", not an integer or float type");
    if (op == kOpTypeArray) {
      const Definition* length = definition(ids.at(1));
      if (!length || !(length->flags & kDefinesConstant) || opcode_of(length->info) != kOpTypeInt)
        return fail("array length " + id_text(ids[1]) + " is not an integer constant");
    }
    if (op == kOpFunction && opcode_of(ids.at(0)) != kOpTypeFunction)
      return fail("function " + id_text(result) + " has type " + id_text(ids[0]) + ", not a function type");
    if (op == kOpExtInst && !(opcode_of(ids.at(0)) == kOpExtInstImport))
      return fail("extended instruction set " + id_text(ids[0]) + " is not an OpExtInstImport");
    return true;
  }

  bool step(size_t where) {
    at = where;
    const uint32_t count = words[at] >> 16, opcode = words[at] & 0xFFFFu;
    instruction = find_instruction(opcode);
    if (!instruction)
      return fail("opcode " + std::to_string(opcode) + " is not one of SPIR-V " + kGrammarVersion + "'s");
    operands = words.subspan(at + 1, count - 1);
    pos = 0;
    result = result_type = 0;
    ids.clear();
    const std::span<const Operand> list(kOperands + instruction->first_operand, instruction->operand_count);
    if (opcode == kOpExtInst) {
      // Operands of sets other than GLSL.std.450 (debug information, printf) are opaque here.
      for (size_t i = 0; i < 4; ++i)
        if (!operand(list[i])) return false;
      if (glsl_std_450.count(ids[0]) && !quantified(list[4])) return false;
      pos = operands.size();
    } else if (opcode == kOpTypeForwardPointer) {
      if (operands.size() != 2) return fail("does not have exactly two operands");
      if (operands[0] == 0 || operands[0] >= bound || definitions.find(operands[0]))
        return fail("declares " + id_text(operands[0]) + ", which is outside the bound or already defined");
      forward_pointers.insert(operands[0]);
      pos = operands.size();
    } else if (!parameters(list)) {
      return false;
    }
    if (pos != operands.size())
      return fail("has " + std::to_string(operands.size() - pos) + " words more than its operands");
    if (!kinds()) return false;
    if (opcode == kOpFunction) in_function = true;
    if (result) {
      Definition& d = definitions.at(result);
      d.defined = true;
      d.opcode = instruction->opcode;
      d.flags = instruction->flags;
      d.info = (opcode == kOpTypeInt || opcode == kOpTypeFloat) ? operands[1] : result_type;
    }
    if (opcode == kOpExtInstImport &&
        std::string_view(reinterpret_cast<const char*>(&operands[1]), (operands.size() - 1) * 4)
                .substr(0, 13) == std::string_view("GLSL.std.450\0", 13))
      glsl_std_450.insert(result);
    if (opcode == kOpFunctionEnd) in_function = false;
    return true;
  }
};

}  // namespace

Result<void> check_structure(std::span<const uint32_t> words) {
  Checker c(words);
  for (size_t at = 5; at < words.size();) {
    const uint32_t count = words[at] >> 16;
    if (count == 0 || count > words.size() - at)
      return detail::failure(ErrorCode::corrupt,
                             "SPIR-V word " + std::to_string(at) +
                                 (count == 0 ? ": instruction with a word count of zero"
                                             : ": instruction runs past the end of the module"));
    if (!c.step(at)) return *c.error;
    at += count;
  }
  for (const Checker::LaterUse& u : c.later)
    if (!c.definitions.find(u.id)) {
      c.fail(u.at, "operand " + id_text(u.id) + " is never defined");
      return *c.error;
    }
  return {};
}

const char* grammar_version() {
  return kGrammarVersion;
}

}  // namespace statepack::spirv
