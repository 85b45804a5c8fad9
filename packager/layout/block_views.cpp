#include "block_views.hpp"

#include <spirv/unified1/spirv.h>

#include <algorithm>
#include <cstring>
#include <map>
#include <optional>
#include <set>

namespace statepack::packager {
namespace {

constexpr size_t kHeaderWords = 5;
constexpr int kMaxTypeDepth = 16;  // nesting of arrays and structs followed; deeper is refused, not recursed

bool is_type(uint32_t op) {
  return op >= SpvOpTypeVoid && op <= SpvOpTypeForwardPointer;
}
bool is_annotation(uint32_t op) {
  return op == SpvOpDecorate || op == SpvOpMemberDecorate || op == SpvOpDecorationGroup ||
         op == SpvOpGroupDecorate || op == SpvOpGroupMemberDecorate || op == SpvOpDecorateId ||
         op == SpvOpDecorateString || op == SpvOpMemberDecorateString;
}

std::string literal(const std::vector<uint32_t>& w, size_t first, size_t end) {
  std::string out;
  for (size_t i = first; i < end; ++i)
    for (int b = 0; b < 4; ++b) {
      const char c = char(w[i] >> (8 * b) & 0xFF);
      if (c == 0) return out;
      out += c;
    }
  return out;
}
std::vector<uint32_t> string_words(const std::string& s) {
  std::vector<uint32_t> out(s.size() / 4 + 1, 0);
  std::memcpy(out.data(), s.data(), s.size());
  return out;
}

// One module, indexed: where each id is defined, its names and decorations.
struct Module {
  std::vector<uint32_t>& w;
  std::vector<size_t> starts;
  std::map<uint32_t, size_t> def;  // result id -> its instruction (types, constants, variables)
  std::map<uint32_t, std::string> name;
  std::map<std::pair<uint32_t, uint32_t>, std::string> member_name;
  std::map<uint32_t, std::vector<size_t>> decorations;                              // target -> OpDecorate
  std::map<std::pair<uint32_t, uint32_t>, std::vector<size_t>> member_decorations;  // (struct, member)
  bool ok = true;

  explicit Module(std::vector<uint32_t>& words) : w(words) {
    for (size_t at = kHeaderWords; at < w.size();) {
      const uint32_t n = w[at] >> 16;
      if (n == 0 || at + n > w.size()) {
        ok = false;
        return;
      }
      starts.push_back(at);
      const uint32_t op = w[at] & 0xFFFFu;
      if (is_type(op) && op != SpvOpTypeForwardPointer && n >= 2) def[w[at + 1]] = at;
      if ((op == SpvOpConstant || op == SpvOpConstantTrue || op == SpvOpConstantFalse ||
           op == SpvOpVariable) &&
          n >= 3)
        def[w[at + 2]] = at;
      if (op == SpvOpName && n >= 3) name[w[at + 1]] = literal(w, at + 2, at + n);
      if (op == SpvOpMemberName && n >= 4) member_name[{w[at + 1], w[at + 2]}] = literal(w, at + 3, at + n);
      if (op == SpvOpDecorate && n >= 3) decorations[w[at + 1]].push_back(at);
      if (op == SpvOpMemberDecorate && n >= 4) member_decorations[{w[at + 1], w[at + 2]}].push_back(at);
      at += n;
    }
  }
  uint32_t op(size_t at) const { return w[at] & 0xFFFFu; }
  uint32_t count(size_t at) const { return w[at] >> 16; }
  std::optional<size_t> defined(uint32_t id) const {
    auto it = def.find(id);
    return it == def.end() ? std::nullopt : std::optional<size_t>(it->second);
  }
  // A member's decorations other than Offset, as (decoration, operands) words, sorted.
  std::vector<std::vector<uint32_t>> member_decorations_of(uint32_t type, uint32_t member) const {
    std::vector<std::vector<uint32_t>> out;
    auto it = member_decorations.find({type, member});
    if (it == member_decorations.end()) return out;
    for (size_t at : it->second)
      if (w[at + 3] != SpvDecorationOffset)
        out.emplace_back(w.begin() + std::ptrdiff_t(at + 3), w.begin() + std::ptrdiff_t(at + count(at)));
    std::sort(out.begin(), out.end());
    return out;
  }
  std::optional<uint32_t> member_offset(uint32_t type, uint32_t member) const {
    auto it = member_decorations.find({type, member});
    if (it == member_decorations.end()) return std::nullopt;
    for (size_t at : it->second)
      if (w[at + 3] == SpvDecorationOffset && count(at) >= 5) return w[at + 4];
    return std::nullopt;
  }
  std::optional<uint32_t> decoration(uint32_t target, uint32_t which) const {
    auto it = decorations.find(target);
    if (it == decorations.end()) return std::nullopt;
    for (size_t at : it->second)
      if (w[at + 2] == which) return count(at) >= 4 ? w[at + 3] : 0;
    return std::nullopt;
  }
  // The value of a 32-bit OpConstant.
  std::optional<uint32_t> constant(uint32_t id) const {
    auto at = defined(id);
    if (!at || op(*at) != SpvOpConstant || count(*at) != 4) return std::nullopt;
    return w[*at + 3];
  }

  // A description of `type` that is equal for equal types in any module ("" when it is not one this
  // merges), and its size in bytes given the decorations of the member that holds it.
  std::string signature(uint32_t type, int depth = 0) const {
    auto at = defined(type);
    if (!at || depth > kMaxTypeDepth) return "";
    const uint32_t o = op(*at), n = count(*at);
    switch (o) {
      case SpvOpTypeBool:
        return "b";
      case SpvOpTypeInt:
        return n >= 4 ? "i" + std::to_string(w[*at + 2]) + (w[*at + 3] ? "s" : "u") : "";
      case SpvOpTypeFloat:
        return n >= 3 ? "f" + std::to_string(w[*at + 2]) : "";
      case SpvOpTypeVector:
      case SpvOpTypeMatrix: {
        const std::string inner = n >= 4 ? signature(w[*at + 2], depth + 1) : "";
        return inner.empty() ? "" : (o == SpvOpTypeVector ? "v" : "m") + std::to_string(w[*at + 3]) + inner;
      }
      case SpvOpTypeArray: {
        const auto length = n >= 4 ? constant(w[*at + 3]) : std::nullopt;
        const std::string inner = n >= 4 ? signature(w[*at + 2], depth + 1) : "";
        if (!length || inner.empty()) return "";
        return "a" + std::to_string(*length) + "s" +
               std::to_string(decoration(type, SpvDecorationArrayStride).value_or(0)) + inner;
      }
      case SpvOpTypeStruct: {
        std::string out = "{";
        for (uint32_t m = 0; m + 2 < n; ++m) {
          const std::string inner = signature(w[*at + 2 + m], depth + 1);
          const auto offset = member_offset(type, m);
          if (inner.empty() || !offset) return "";
          out += std::to_string(*offset) + ":" + inner;
          for (const auto& d : member_decorations_of(type, m))
            for (uint32_t x : d) out += "," + std::to_string(x);
          out += ";";
        }
        return out + "}";
      }
      default:
        return "";
    }
  }
  uint64_t size(uint32_t type, const std::vector<std::vector<uint32_t>>& holder, int depth = 0) const {
    auto at = defined(type);
    if (!at || depth > kMaxTypeDepth) return 0;
    const uint32_t o = op(*at), n = count(*at);
    auto stride_of = [&](uint32_t which) -> uint64_t {
      for (const auto& d : holder)
        if (d.size() >= 2 && d[0] == which) return d[1];
      return 0;
    };
    switch (o) {
      case SpvOpTypeBool:
        return 4;
      case SpvOpTypeInt:
      case SpvOpTypeFloat:
        return n >= 3 ? w[*at + 2] / 8 : 0;
      case SpvOpTypeVector:
        return n >= 4 ? w[*at + 3] * size(w[*at + 2], {}, depth + 1) : 0;
      case SpvOpTypeMatrix: {
        const bool row_major = std::any_of(holder.begin(), holder.end(), [](const auto& d) {
          return !d.empty() && d[0] == SpvDecorationRowMajor;
        });
        auto column = defined(w[*at + 2]);
        const uint64_t rows = column && count(*column) >= 4 ? w[*column + 3] : 4;
        return stride_of(SpvDecorationMatrixStride) * (row_major ? rows : w[*at + 3]);
      }
      case SpvOpTypeArray:
        return uint64_t(constant(w[*at + 3]).value_or(0)) *
               decoration(type, SpvDecorationArrayStride).value_or(0);
      case SpvOpTypeStruct: {
        uint64_t end = 0;
        for (uint32_t m = 0; m + 2 < n; ++m)
          end = std::max(end, member_offset(type, m).value_or(0) +
                                  size(w[*at + 2 + m], member_decorations_of(type, m), depth + 1));
        return end;
      }
      default:
        return 0;
    }
  }
  // A struct's members as entries of its signature, in order; empty for other types.
  std::vector<std::string> fields(uint32_t type) const {
    std::vector<std::string> out;
    auto at = defined(type);
    if (!at || op(*at) != SpvOpTypeStruct) return out;
    for (uint32_t m = 0; m + 2 < count(*at); ++m) {
      std::string field =
          std::to_string(member_offset(type, m).value_or(~0u)) + ":" + signature(w[*at + 2 + m]);
      for (const auto& d : member_decorations_of(type, m))
        for (uint32_t x : d) field += "," + std::to_string(x);
      out.push_back(std::move(field));
    }
    return out;
  }
  // The block struct a variable points to (0 when it is not one).
  uint32_t block_of(uint32_t variable) const {
    auto v = defined(variable);
    if (!v || op(*v) != SpvOpVariable) return 0;
    auto p = defined(w[*v + 1]);
    return p && op(*p) == SpvOpTypePointer ? w[*p + 3] : 0;
  }
};

struct Member {
  uint32_t offset = 0;
  uint64_t size = 0;
  std::string signature, name;
  // A struct member's own members ("offset:signature,decorations"), to merge HLSL's
  // `cbuffer ubo { UBO ubo; }` whose struct one stage declares in part: one must be a prefix of the other.
  std::vector<std::string> fields;
  std::vector<std::vector<uint32_t>> decorations;
  size_t view = 0;     // the view that declares it
  uint32_t index = 0;  // its index in that view's block
  uint32_t type = 0;   // in that view's module
};

// The views' members; "" or why they cannot be compared.
std::string members_of(const std::vector<BlockView>& views, std::vector<Module>& modules,
                       std::vector<std::vector<Member>>& out) {
  for (size_t v = 0; v < views.size(); ++v) {
    Module& m = modules[v];
    const uint32_t block = m.block_of(views[v].variable);
    auto at = m.defined(block);
    if (!at || m.op(*at) != SpvOpTypeStruct) return views[v].shader + ": the block is not a struct";
    auto& list = out.emplace_back();
    for (uint32_t i = 0; i + 2 < m.count(*at); ++i) {
      Member member;
      member.type = m.w[*at + 2 + i];
      member.decorations = m.member_decorations_of(block, i);
      member.signature = m.signature(member.type);
      member.fields = m.fields(member.type);
      member.size = m.size(member.type, member.decorations);
      const auto offset = m.member_offset(block, i);
      if (member.signature.empty() || !offset)
        return views[v].shader + ": member " + std::to_string(i) +
               " of the block is of a kind this does not merge";
      member.offset = *offset;
      member.name =
          m.member_name.count({block, i}) ? m.member_name[{block, i}] : "member" + std::to_string(i);
      member.view = v;
      member.index = i;
      list.push_back(std::move(member));
    }
  }
  return "";
}

std::string describe(const Member& m, const std::vector<BlockView>& views) {
  return "'" + m.name + "' (" + std::to_string(m.size) + " bytes at offset " + std::to_string(m.offset) +
         ") in " + views[m.view].shader;
}

// The merged members, by offset; "" or the conflict.
std::string merged_members(const std::vector<BlockView>& views,
                           const std::vector<std::vector<Member>>& members,
                           std::vector<const Member*>& merged) {
  std::map<uint32_t, const Member*> by_offset;
  for (const auto& list : members)
    for (const Member& m : list) {
      auto [it, inserted] = by_offset.emplace(m.offset, &m);
      if (inserted || (it->second->signature == m.signature && it->second->decorations == m.decorations))
        continue;
      // Two structs at one offset, one declaring the first members of the other: the larger is the view.
      const Member& a = *it->second;
      const Member& shorter = a.fields.size() <= m.fields.size() ? a : m;
      const Member& longer = &shorter == &a ? m : a;
      const bool prefix = !shorter.fields.empty() && a.decorations == m.decorations &&
                          std::equal(shorter.fields.begin(), shorter.fields.end(), longer.fields.begin());
      if (!prefix)
        return describe(a, views) + " and " + describe(m, views) + " are different types at one offset";
      it->second = &longer;
    }
  const Member* previous = nullptr;
  for (const auto& [offset, m] : by_offset) {
    if (previous && previous->offset + previous->size > offset)
      return describe(*previous, views) + " and " + describe(*m, views) + " overlap";
    previous = m;
    merged.push_back(m);
  }
  return "";
}

// New instructions for one module, placed where the layout rules want them.
struct Additions {
  std::vector<uint32_t> names, annotations, types;
};

void emit(std::vector<uint32_t>& out, uint32_t op, std::initializer_list<uint32_t> operands,
          const std::vector<uint32_t>& tail = {}) {
  out.push_back(uint32_t(1 + operands.size() + tail.size()) << 16 | op);
  out.insert(out.end(), operands);
  out.insert(out.end(), tail.begin(), tail.end());
}

// Copies `type` of module `from` into `to` (reusing what `to` has where the rules require), its new
// instructions into `add`; 0 when it cannot.
uint32_t import_type(const Module& from, uint32_t type, Module& to, uint32_t& bound, Additions& add,
                     std::map<uint32_t, uint32_t>& imported, int depth = 0) {
  if (auto done = imported.find(type); done != imported.end()) return done->second;
  auto at = from.defined(type);
  if (!at || depth > kMaxTypeDepth) return 0;
  const uint32_t op = from.op(*at), n = from.count(*at);
  std::vector<uint32_t> operands(from.w.begin() + std::ptrdiff_t(*at + 2),
                                 from.w.begin() + std::ptrdiff_t(*at + n));
  if (op == SpvOpTypeVector || op == SpvOpTypeMatrix || op == SpvOpTypeArray) {
    const uint32_t inner = import_type(from, operands[0], to, bound, add, imported, depth + 1);
    if (!inner) return 0;
    operands[0] = inner;
  }
  if (op == SpvOpTypeArray) {  // its length: a 32-bit constant of an integer type
    auto length_at = from.defined(operands[1]);
    if (!length_at || from.op(*length_at) != SpvOpConstant || from.count(*length_at) != 4) return 0;
    const uint32_t length_type =
        import_type(from, from.w[*length_at + 1], to, bound, add, imported, depth + 1);
    if (!length_type) return 0;
    const uint32_t length = bound++;
    emit(add.types, SpvOpConstant, {length_type, length, from.w[*length_at + 3]});
    operands[1] = length;
  }
  if (op == SpvOpTypeStruct) {
    for (uint32_t& member : operands) {
      member = import_type(from, member, to, bound, add, imported, depth + 1);
      if (!member) return 0;
    }
  }
  // Scalars, vectors and matrices are unique in a module: reuse the one `to` declares.
  if (op == SpvOpTypeBool || op == SpvOpTypeInt || op == SpvOpTypeFloat || op == SpvOpTypeVector ||
      op == SpvOpTypeMatrix)
    for (const auto& [id, def] : to.def)
      if (to.op(def) == op && to.count(def) == n &&
          std::equal(operands.begin(), operands.end(), to.w.begin() + std::ptrdiff_t(def + 2)))
        return imported[type] = id;
  if (op != SpvOpTypeBool && op != SpvOpTypeInt && op != SpvOpTypeFloat && op != SpvOpTypeVector &&
      op != SpvOpTypeMatrix && op != SpvOpTypeArray && op != SpvOpTypeStruct)
    return 0;
  const uint32_t id = bound++;
  add.types.push_back(n << 16 | op);
  add.types.push_back(id);
  add.types.insert(add.types.end(), operands.begin(), operands.end());
  if (auto stride = from.decoration(type, SpvDecorationArrayStride))
    emit(add.annotations, SpvOpDecorate, {id, SpvDecorationArrayStride, *stride});
  if (op == SpvOpTypeStruct) {
    if (from.name.count(type)) emit(add.names, SpvOpName, {id}, string_words(from.name.at(type)));
    for (uint32_t m = 0; m < operands.size(); ++m) {
      if (auto offset = from.member_offset(type, m))
        emit(add.annotations, SpvOpMemberDecorate, {id, m, SpvDecorationOffset, *offset});
      for (const auto& d : from.member_decorations_of(type, m))
        emit(add.annotations, SpvOpMemberDecorate, {id, m}, d);
      if (auto name = from.member_name.find({type, m}); name != from.member_name.end())
        emit(add.names, SpvOpMemberName, {id, m}, string_words(name->second));
    }
  }
  return imported[type] = id;
}

// What rewriting one module's block needs across its steps.
struct BlockRewrite {
  size_t v = 0;
  uint32_t variable = 0, old_block = 0, storage = 0, bound = 0;
  Additions add;
  std::map<uint32_t, uint32_t> new_index;  // old member index -> merged index
  std::map<uint32_t, uint32_t> grown;      // old member index -> pointer to the larger struct it became
  std::vector<uint32_t> member_types;      // of the merged struct
};

// The merged struct's member types as module `r.v` declares them: its own, or imported from the stage
// that declares the member.
std::string declare_member_types(BlockRewrite& r, const std::vector<BlockView>& views,
                                 std::vector<Module>& modules, const std::vector<const Member*>& merged) {
  Module& m = modules[r.v];
  for (uint32_t i = 0; i < merged.size(); ++i) {
    const Member& member = *merged[i];
    uint32_t type = 0;
    if (member.view == r.v) {
      type = member.type;
      r.new_index[member.index] = i;
    } else {
      // Declared in this module too at that offset (with another name, maybe): the module's own, unless it
      // is the first members of the merged struct, which is then declared here with those members' types.
      std::map<uint32_t, uint32_t> imported;
      for (uint32_t k = 0; !type && k + 2 < m.count(*m.defined(r.old_block)); ++k) {
        if (m.member_offset(r.old_block, k) != member.offset) continue;
        r.new_index[k] = i;
        const uint32_t own = m.w[*m.defined(r.old_block) + 2 + k];
        if (m.signature(own) == member.signature) {
          type = own;
          continue;
        }
        const Module& from = modules[member.view];
        const size_t from_at = *from.defined(member.type), own_at = *m.defined(own);
        for (uint32_t f = 0; f + 2 < m.count(own_at); ++f)
          imported[from.w[from_at + 2 + f]] = m.w[own_at + 2 + f];
        r.grown[k] = 0;  // its pointer type, made below
      }
      if (!type) type = import_type(modules[member.view], member.type, m, r.bound, r.add, imported);
      if (!type) return views[r.v].shader + ": cannot declare member '" + member.name + "' there";
      for (auto& [k, pointer] : r.grown)
        if (pointer == 0 && r.new_index[k] == i) {
          pointer = r.bound++;
          emit(r.add.types, SpvOpTypePointer, {pointer, r.storage, type});
        }
    }
    r.member_types.push_back(type);
  }
  return "";
}

// The merged struct, its decorations and names, and the pointer to it; returns that pointer.
uint32_t declare_block(BlockRewrite& r, Module& m, const std::vector<const Member*>& merged) {
  const uint32_t block = r.bound++, pointer = r.bound++;
  Additions& add = r.add;
  add.types.push_back(uint32_t(2 + r.member_types.size()) << 16 | SpvOpTypeStruct);
  add.types.push_back(block);
  add.types.insert(add.types.end(), r.member_types.begin(), r.member_types.end());
  emit(add.types, SpvOpTypePointer, {pointer, r.storage, block});
  if (m.name.count(r.old_block)) emit(add.names, SpvOpName, {block}, string_words(m.name[r.old_block]));
  if (auto it = m.decorations.find(r.old_block); it != m.decorations.end())
    for (size_t at : it->second) {
      std::vector<uint32_t> d(m.w.begin() + std::ptrdiff_t(at),
                              m.w.begin() + std::ptrdiff_t(at + m.count(at)));
      d[1] = block;
      add.annotations.insert(add.annotations.end(), d.begin(), d.end());
    }
  for (uint32_t i = 0; i < merged.size(); ++i) {
    emit(add.annotations, SpvOpMemberDecorate, {block, i, SpvDecorationOffset, merged[i]->offset});
    for (const auto& d : merged[i]->decorations) emit(add.annotations, SpvOpMemberDecorate, {block, i}, d);
    emit(add.names, SpvOpMemberName, {block, i}, string_words(merged[i]->name));
  }
  return pointer;
}

// Access chains into the block, with their new first index (and result type where the member grew).
struct ChainEdits {
  std::map<size_t, uint32_t> retarget;  // access chain -> its new first index id
  std::map<size_t, uint32_t> retyped;   // access chain -> its new result type
};

std::string edit_access_chains(BlockRewrite& r, const std::string& shader, Module& m, ChainEdits& edits) {
  std::set<uint32_t> stops_at_grown;                                 // pointers to a grown member
  std::map<std::pair<uint32_t, uint32_t>, uint32_t> index_constant;  // (type, value) -> id
  const uint32_t variable = r.variable;
  for (size_t at : m.starts) {
    const uint32_t op = m.op(at), n = m.count(at);
    const bool chain = op == SpvOpAccessChain || op == SpvOpInBoundsAccessChain;
    if (chain && n >= 5 && m.w[at + 3] == variable) {
      auto old_index = m.constant(m.w[at + 4]);
      if (!old_index || !r.new_index.count(*old_index))
        return shader + ": an access to the block this does not follow";
      const uint32_t type = m.w[*m.defined(m.w[at + 4]) + 1];
      auto [it, added] = index_constant.try_emplace({type, r.new_index[*old_index]}, 0);
      if (added) {
        it->second = r.bound++;
        emit(r.add.types, SpvOpConstant, {type, it->second, r.new_index[*old_index]});
      }
      edits.retarget[at] = it->second;
      // A chain that stops at a member grown into the larger struct points to that struct now; what it
      // leads to may only index further (the members it reaches keep their indices).
      if (auto g = r.grown.find(*old_index); g != r.grown.end() && n == 5) {
        edits.retyped[at] = g->second;
        stops_at_grown.insert(m.w[at + 2]);
      }
      continue;
    }
    if (chain && n >= 4 && stops_at_grown.count(m.w[at + 3])) continue;
    // Any other instruction that takes the block's pointer (loading or copying it whole, passing it on).
    const bool takes_pointer =
        (op == SpvOpLoad && n >= 4 && m.w[at + 3] == variable) ||
        ((op == SpvOpStore || op == SpvOpCopyMemory) && n >= 3 &&
         (m.w[at + 1] == variable || m.w[at + 2] == variable)) ||
        ((op == SpvOpCopyObject || op == SpvOpPtrAccessChain || op == SpvOpInBoundsPtrAccessChain) &&
         n >= 4 && m.w[at + 3] == variable) ||
        ((op == SpvOpFunctionCall || op == SpvOpPhi || op == SpvOpSelect) &&
         std::find(m.w.begin() + std::ptrdiff_t(at + 3), m.w.begin() + std::ptrdiff_t(at + n), variable) !=
             m.w.begin() + std::ptrdiff_t(at + n));
    if (takes_pointer)
      return shader + ": uses the block whole (a load, a copy, a call), which this does not rewrite";
    for (uint32_t k = 1; k < n && (op == SpvOpLoad || op == SpvOpCopyObject || op == SpvOpStore ||
                                   op == SpvOpCopyMemory || op == SpvOpFunctionCall);
         ++k)
      if (stops_at_grown.count(m.w[at + k]))
        return shader + ": uses a member the other stage declares larger whole, which this does not rewrite";
  }
  return "";
}

// The module again, with the additions where the layout rules put them: names after the other names,
// decorations before the first type, and the new types and constants, then the block's variable
// (moved: the types it now points to use types declared anywhere before), before the first function.
std::vector<uint32_t> reassemble(const Module& m, BlockRewrite& r, uint32_t pointer,
                                 const ChainEdits& edits) {
  const size_t var_at = *m.defined(r.variable);
  size_t names_at = 0, annotations_at = 0, globals_end = m.w.size();
  for (size_t at : m.starts) {
    const uint32_t op = m.op(at);
    if (op == SpvOpName || op == SpvOpMemberName) names_at = at + m.count(at);
    if (!annotations_at && (is_type(op) || op == SpvOpConstant || op == SpvOpVariable)) annotations_at = at;
    if (!names_at && (op == SpvOpModuleProcessed || is_annotation(op))) names_at = at;
    if (op == SpvOpFunction && globals_end == m.w.size()) globals_end = at;
  }
  if (!names_at) names_at = annotations_at;
  Additions& add = r.add;
  std::vector<uint32_t> moved(m.w.begin() + std::ptrdiff_t(var_at),
                              m.w.begin() + std::ptrdiff_t(var_at + m.count(var_at)));
  moved[1] = pointer;
  add.types.insert(add.types.end(), moved.begin(), moved.end());
  std::vector<uint32_t> out(m.w.begin(), m.w.begin() + kHeaderWords);
  for (size_t at : m.starts) {
    if (at == names_at) out.insert(out.end(), add.names.begin(), add.names.end());
    if (at == annotations_at) out.insert(out.end(), add.annotations.begin(), add.annotations.end());
    if (at == globals_end) out.insert(out.end(), add.types.begin(), add.types.end());
    if (at == var_at) continue;
    const size_t first = out.size();
    out.insert(out.end(), m.w.begin() + std::ptrdiff_t(at), m.w.begin() + std::ptrdiff_t(at + m.count(at)));
    if (auto it = edits.retarget.find(at); it != edits.retarget.end()) out[first + 4] = it->second;
    if (auto it = edits.retyped.find(at); it != edits.retyped.end()) out[first + 1] = it->second;
  }
  if (names_at >= m.w.size()) out.insert(out.end(), add.names.begin(), add.names.end());
  if (globals_end >= m.w.size()) out.insert(out.end(), add.types.begin(), add.types.end());
  out[3] = r.bound;
  return out;
}

// Module `v` with its block rewritten as `merged`, in `result` (the modules stay as they are: the others
// import member types from them).
std::string rewrite(size_t v, const std::vector<BlockView>& views, std::vector<Module>& modules,
                    const std::vector<const Member*>& merged, std::vector<uint32_t>& result) {
  Module& m = modules[v];
  BlockRewrite r;
  r.v = v;
  r.variable = views[v].variable;
  r.old_block = m.block_of(r.variable);
  r.storage = m.w[*m.defined(m.w[*m.defined(r.variable) + 1]) + 2];
  r.bound = m.w[3];
  if (std::string error = declare_member_types(r, views, modules, merged); !error.empty()) return error;
  const uint32_t pointer = declare_block(r, m, merged);
  ChainEdits edits;
  if (std::string error = edit_access_chains(r, views[v].shader, m, edits); !error.empty()) return error;
  result = reassemble(m, r, pointer, edits);
  return "";
}

// The views' modules parsed and their members merged (empty, or what stops them).
std::string merge_views(const std::vector<BlockView>& views, std::vector<Module>& modules,
                        std::vector<std::vector<Member>>& members, std::vector<const Member*>& merged) {
  for (const BlockView& v : views) {
    modules.emplace_back(*v.spirv);
    if (!modules.back().ok) return v.shader + ": the module is malformed";
  }
  if (std::string problem = members_of(views, modules, members); !problem.empty()) return problem;
  return merged_members(views, members, merged);
}

}  // namespace

std::string block_views_conflict(const std::vector<BlockView>& views) {
  std::vector<Module> modules;
  std::vector<std::vector<Member>> members;
  std::vector<const Member*> merged;
  return merge_views(views, modules, members, merged);
}

std::string merge_block_views(const std::vector<BlockView>& views) {
  std::vector<Module> modules;
  std::vector<std::vector<Member>> members;
  std::vector<const Member*> merged;
  if (std::string conflict = merge_views(views, modules, members, merged); !conflict.empty()) return conflict;
  // All or nothing: the modules are replaced once every one is rewritten.
  std::vector<std::vector<uint32_t>> results(views.size());
  for (size_t v = 0; v < views.size(); ++v)
    if (std::string problem = rewrite(v, views, modules, merged, results[v]); !problem.empty())
      return problem;
  for (size_t v = 0; v < views.size(); ++v) *views[v].spirv = std::move(results[v]);
  return "";
}

}  // namespace statepack::packager
