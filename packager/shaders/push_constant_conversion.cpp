#include "push_constant_conversion.hpp"

#include <spirv/unified1/spirv.h>

#include <map>
#include <set>

namespace statepack::packager {
namespace {

constexpr size_t kHeaderWords = 5;

// Each instruction's first word, in order; empty when the module is malformed.
std::vector<size_t> instruction_starts(const std::vector<uint32_t>& spirv) {
  std::vector<size_t> out;
  for (size_t at = kHeaderWords; at < spirv.size();) {
    const uint32_t count = spirv[at] >> 16;
    if (count == 0 || at + count > spirv.size()) return {};
    out.push_back(at);
    at += count;
  }
  return out;
}

bool derives_pointer(uint32_t op) {
  return op == SpvOpAccessChain || op == SpvOpInBoundsAccessChain || op == SpvOpPtrAccessChain ||
         op == SpvOpInBoundsPtrAccessChain || op == SpvOpCopyObject;
}

}  // namespace

std::string uniform_block_to_push_constants(std::vector<uint32_t>& spirv, uint32_t variable) {
  const std::vector<size_t> starts = instruction_starts(spirv);
  if (starts.empty()) return "the module is malformed";
  auto op_of = [&](size_t at) { return spirv[at] & 0xFFFFu; };
  auto count_of = [&](size_t at) { return spirv[at] >> 16; };

  std::map<std::pair<uint32_t, uint32_t>, uint32_t> pointer_id;  // (storage class, pointee) -> type id
  std::map<uint32_t, std::pair<uint32_t, uint32_t>> pointer_of;  // type id -> (storage class, pointee)
  std::map<uint32_t, size_t> declared_at;                        // pointer type id -> its instruction
  std::set<uint32_t> blocks, buffer_blocks;
  size_t variable_at = 0;
  uint32_t existing_push_constants = 0;
  for (size_t at : starts) {
    const uint32_t op = op_of(at), n = count_of(at);
    if (op == SpvOpTypePointer && n >= 4) {
      pointer_id.emplace(std::pair{spirv[at + 2], spirv[at + 3]}, spirv[at + 1]);
      pointer_of[spirv[at + 1]] = {spirv[at + 2], spirv[at + 3]};
      declared_at[spirv[at + 1]] = at;
    } else if (op == SpvOpVariable && n >= 4) {
      if (spirv[at + 2] == variable) variable_at = at;
      if (spirv[at + 3] == SpvStorageClassPushConstant) existing_push_constants = spirv[at + 2];
    } else if (op == SpvOpDecorate && n >= 3) {
      if (spirv[at + 2] == SpvDecorationBlock) blocks.insert(spirv[at + 1]);
      if (spirv[at + 2] == SpvDecorationBufferBlock) buffer_blocks.insert(spirv[at + 1]);
    }
  }
  if (variable_at == 0 || spirv[variable_at + 3] != SpvStorageClassUniform)
    return "it is not a uniform buffer in the shader";
  const auto block_pointer = pointer_of.find(spirv[variable_at + 1]);
  if (block_pointer == pointer_of.end()) return "its type is not a pointer";
  const uint32_t block = block_pointer->second.second;
  if (buffer_blocks.count(block) || !blocks.count(block))
    return "it is not a uniform block (a storage buffer, or an array of blocks)";
  if (existing_push_constants != 0)
    return "the shader declares push constants of its own (a stage has one push-constant block)";

  // Every pointer the shader derives from the block (SSA: definitions come before their uses, phi aside),
  // with the pointee its PushConstant pointer type must have.
  std::set<uint32_t> derived{variable};
  std::map<size_t, uint32_t> retyped;  // instruction -> pointee of its new result type
  for (size_t at : starts) {
    const uint32_t op = op_of(at), n = count_of(at);
    if (derives_pointer(op) && n >= 4 && derived.count(spirv[at + 3])) {
      auto type = pointer_of.find(spirv[at + 1]);
      if (type == pointer_of.end()) return "a pointer into it has no pointer type";
      derived.insert(spirv[at + 2]);
      retyped[at] = type->second.second;
      continue;
    }
    // Pointers passed on, or merged with other pointers, would need their functions and merges retyped:
    // HLSL is legalized (functions inlined) and GLSL passes blocks by value, so neither happens here.
    const bool passes_pointers = op == SpvOpFunctionCall || op == SpvOpPhi || op == SpvOpSelect;
    if (passes_pointers)
      for (uint32_t w = 3; w < n; ++w)
        if (derived.count(spirv[at + w]))
          return std::string("a pointer into it is passed to ") +
                 (op == SpvOpFunctionCall ? "a function" : "a phi or select") +
                 ", which this conversion does not follow";
  }

  // The PushConstant pointer types, reused where the module has them, else declared right after the
  // Uniform pointer type to the same pointee (which comes after the pointee's own declaration).
  uint32_t bound = spirv[3];
  std::map<size_t, std::vector<uint32_t>> inserted_after;
  std::map<uint32_t, uint32_t> push_pointer;  // pointee -> PushConstant pointer type id
  auto push_pointer_to = [&](uint32_t pointee, size_t uniform_declaration) {
    if (auto known = push_pointer.find(pointee); known != push_pointer.end()) return known->second;
    if (auto existing = pointer_id.find({SpvStorageClassPushConstant, pointee}); existing != pointer_id.end())
      return push_pointer[pointee] = existing->second;
    const uint32_t id = bound++;
    auto& words = inserted_after[uniform_declaration];
    words.insert(words.end(), {4u << 16 | SpvOpTypePointer, id, SpvStorageClassPushConstant, pointee});
    return push_pointer[pointee] = id;
  };
  const uint32_t variable_type = push_pointer_to(block, declared_at.at(spirv[variable_at + 1]));
  std::map<size_t, uint32_t> new_result_type;
  for (const auto& [at, pointee] : retyped) {
    const auto uniform = pointer_id.find({SpvStorageClassUniform, pointee});
    if (uniform == pointer_id.end()) return "a pointer into it is not a Uniform pointer";
    new_result_type[at] = push_pointer_to(pointee, declared_at.at(uniform->second));
  }

  std::vector<uint32_t> out(spirv.begin(), spirv.begin() + kHeaderWords);
  out.reserve(spirv.size() + 4 * push_pointer.size());
  for (size_t at : starts) {
    const uint32_t op = op_of(at), n = count_of(at);
    if (op == SpvOpDecorate && n >= 3 && spirv[at + 1] == variable &&
        (spirv[at + 2] == SpvDecorationDescriptorSet || spirv[at + 2] == SpvDecorationBinding))
      continue;  // push constants have no descriptor
    const size_t first = out.size();
    out.insert(out.end(), spirv.begin() + std::ptrdiff_t(at), spirv.begin() + std::ptrdiff_t(at + n));
    if (at == variable_at) {
      out[first + 1] = variable_type;
      out[first + 3] = SpvStorageClassPushConstant;
    } else if (auto type = new_result_type.find(at); type != new_result_type.end()) {
      out[first + 1] = type->second;
    }
    if (auto extra = inserted_after.find(at); extra != inserted_after.end())
      out.insert(out.end(), extra->second.begin(), extra->second.end());
  }
  out[3] = bound;
  spirv = std::move(out);
  return "";
}

}  // namespace statepack::packager
