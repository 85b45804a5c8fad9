#include "hlsl_vertex_inputs.hpp"

#include <spirv/unified1/spirv.h>

#include <algorithm>
#include <cctype>
#include <map>

namespace statepack::packager {
namespace {

constexpr size_t kHeaderWords = 5;

// Calls visit(opcode, words of the instruction) for each instruction; stops at a malformed one.
template <typename Visit>
void for_each_instruction(std::span<const uint32_t> spirv, Visit visit) {
  for (size_t at = kHeaderWords; at < spirv.size();) {
    const uint32_t count = spirv[at] >> 16;
    if (count == 0 || at + count > spirv.size()) return;
    visit(spirv[at] & 0xFFFFu, spirv.subspan(at, count), at);
    at += count;
  }
}

// A literal string operand starting at word `first`.
std::string literal_string(std::span<const uint32_t> words, size_t first) {
  std::string out;
  for (size_t w = first; w < words.size(); ++w)
    for (int b = 0; b < 4; ++b) {
      const char c = char(words[w] >> (8 * b) & 0xFF);
      if (c == 0) return out;
      out += c;
    }
  return out;
}

bool iequals(std::string_view a, std::string_view b) {
  return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
           return std::toupper(static_cast<unsigned char>(x)) == std::toupper(static_cast<unsigned char>(y));
         });
}

// The locations an input of type `type` takes: 64-bit vectors of 3 or 4 and matrices and arrays take
// several; anything this does not size takes one.
struct Types {
  std::map<uint32_t, std::span<const uint32_t>> by_id;  // type and constant instructions by result id
  std::map<uint32_t, uint32_t> pointee;                 // pointer type -> pointee
  uint32_t locations(uint32_t type, int depth = 0) const {
    auto it = by_id.find(type);
    if (it == by_id.end() || depth > 8) return 1;
    const auto w = it->second;
    const uint32_t op = w[0] & 0xFFFFu;
    if (op == SpvOpTypeVector && w.size() >= 4) {
      auto component = by_id.find(w[2]);
      const bool wide =
          component != by_id.end() && component->second.size() >= 3 && component->second[2] == 64;
      return wide && w[3] > 2 ? 2 : 1;
    }
    if (op == SpvOpTypeMatrix && w.size() >= 4) return w[3] * locations(w[2], depth + 1);
    if (op == SpvOpTypeArray && w.size() >= 4) {
      auto length = by_id.find(w[3]);
      const uint32_t n = length != by_id.end() && length->second.size() >= 4 ? length->second[3] : 1;
      return std::min<uint32_t>(n, 64) * locations(w[2], depth + 1);
    }
    return 1;
  }
};

}  // namespace

std::vector<VertexInputSemantic> vertex_input_semantics(std::span<const uint32_t> spirv) {
  std::map<uint32_t, std::string> semantic_of;
  std::vector<uint32_t> inputs;
  for_each_instruction(spirv, [&](uint32_t op, std::span<const uint32_t> w, size_t) {
    if (op == SpvOpDecorateString && w.size() >= 4 && w[2] == SpvDecorationUserSemantic)
      semantic_of[w[1]] = literal_string(w, 3);
    else if (op == SpvOpVariable && w.size() >= 4 && w[3] == SpvStorageClassInput)
      inputs.push_back(w[2]);
  });
  std::vector<VertexInputSemantic> out;
  for (uint32_t id : inputs)
    if (auto it = semantic_of.find(id); it != semantic_of.end()) out.push_back({id, it->second});
  return out;
}

std::optional<uint32_t> attrib_index(std::string_view semantic) {
  if (semantic.size() < 6 || !iequals(semantic.substr(0, 6), "ATTRIB")) return std::nullopt;
  uint64_t n = 0;
  for (char c : semantic.substr(6)) {
    if (c < '0' || c > '9') return std::nullopt;
    n = n * 10 + uint32_t(c - '0');
    if (n > 0xFFFF) return std::nullopt;  // far past any device's vertex attributes
  }
  return uint32_t(n);
}

bool semantic_matches(std::string_view semantic, std::string_view name, uint32_t index) {
  if (semantic.size() < name.size() || !iequals(semantic.substr(0, name.size()), name)) return false;
  std::string_view digits = semantic.substr(name.size());
  if (digits.empty()) return index == 0;
  if (digits.size() > 1 && digits[0] == '0') return false;
  uint64_t n = 0;
  for (char c : digits) {
    if (c < '0' || c > '9') return false;
    n = n * 10 + uint32_t(c - '0');
    if (n > 0xFFFFFFFFu) return false;
  }
  return n == index;
}

bool set_location(std::vector<uint32_t>& spirv, uint32_t variable, uint32_t location) {
  bool found = false;
  for_each_instruction(spirv, [&](uint32_t op, std::span<const uint32_t> w, size_t at) {
    if (op == SpvOpDecorate && w.size() >= 4 && w[1] == variable && w[2] == SpvDecorationLocation) {
      spirv[at + 3] = location;
      found = true;
    }
  });
  return found;
}

std::string place_attrib_inputs(std::vector<uint32_t>& spirv,
                                const std::vector<VertexInputSemantic>& inputs) {
  // Every input's location after the move, and how many it takes, to find two that would overlap.
  Types types;
  std::map<uint32_t, uint32_t> type_of, location_of;
  std::map<uint32_t, std::string> name_of;
  for_each_instruction(spirv, [&](uint32_t op, std::span<const uint32_t> w, size_t) {
    if ((op >= SpvOpTypeVoid && op <= SpvOpTypeForwardPointer) || op == SpvOpConstant) {
      if (op == SpvOpConstant && w.size() >= 4)
        types.by_id[w[2]] = w;
      else if (w.size() >= 2)
        types.by_id[w[1]] = w;
      if (op == SpvOpTypePointer && w.size() >= 4) types.pointee[w[1]] = w[3];
    } else if (op == SpvOpVariable && w.size() >= 4 && w[3] == SpvStorageClassInput) {
      type_of[w[2]] = types.pointee.count(w[1]) ? types.pointee.at(w[1]) : 0;
    } else if (op == SpvOpDecorate && w.size() >= 4 && w[2] == SpvDecorationLocation) {
      location_of[w[1]] = w[3];
    } else if (op == SpvOpName && w.size() >= 3) {
      name_of[w[1]] = literal_string(w, 2);
    }
  });
  std::map<uint32_t, std::string> semantic_of;
  for (const VertexInputSemantic& input : inputs) {
    semantic_of[input.variable] = input.semantic;
    if (auto n = attrib_index(input.semantic); n && location_of.count(input.variable)) {
      location_of[input.variable] = *n;
      set_location(spirv, input.variable, *n);
    }
  }
  auto describe = [&](uint32_t id) {
    std::string name = name_of.count(id) ? name_of[id] : "%" + std::to_string(id);
    return "'" + name + "'" + (semantic_of.count(id) ? " (" + semantic_of[id] + ")" : "");
  };
  std::map<uint32_t, uint32_t> owner;  // location -> variable
  for (const auto& [id, type] : type_of) {
    auto at = location_of.find(id);
    if (at == location_of.end()) continue;  // a built-in
    const uint32_t count = types.locations(type);
    for (uint32_t l = at->second; l < at->second + count; ++l) {
      auto [it, inserted] = owner.emplace(l, id);
      if (!inserted)
        return "vertex inputs " + describe(it->second) + " and " + describe(id) + " both read location " +
               std::to_string(l) + " (an input of semantic ATTRIBn reads location n, as in Diligent)";
    }
  }
  return "";
}

}  // namespace statepack::packager
