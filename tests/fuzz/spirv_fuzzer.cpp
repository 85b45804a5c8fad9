// libFuzzer target for the reader's SPIR-V checks (format/spirv_structure.cpp, then the walk), with a
// structure-aware mutator. Inputs are SPIR-V modules (seeds: the project's shaders, compiled by
// glslangValidator at build time). Most mutations keep the header and the instruction stream intact and
// edit what the structure check is about: an operand (to another result id, an id nothing defines, the
// bound, 0), a type operand, a decoration or capability number, an instruction dropped, duplicated,
// swapped with its neighbour or given another word count. libFuzzer's own byte mutations do the rest.
// Whatever passes must walk without a sanitizer report; run by the test `fuzz.spirv_reader`.
#include <algorithm>
#include <cstring>
#include <iterator>
#include <random>
#include <vector>

#include "format/spirv_walk.hpp"

extern "C" size_t LLVMFuzzerMutate(uint8_t* data, size_t size, size_t max_size);

namespace {

std::vector<uint32_t> words_of(const uint8_t* data, size_t size) {
  std::vector<uint32_t> words(size / 4);
  if (!words.empty()) std::memcpy(words.data(), data, words.size() * 4);
  return words;
}

// Where each instruction starts, as far as the word counts hold.
std::vector<size_t> instructions_of(const std::vector<uint32_t>& words) {
  std::vector<size_t> starts;
  for (size_t at = 5; at < words.size() && (words[at] >> 16) != 0 && (words[at] >> 16) <= words.size() - at;
       at += words[at] >> 16)
    starts.push_back(at);
  return starts;
}

}  // namespace

extern "C" size_t LLVMFuzzerCustomMutator(uint8_t* data, size_t size, size_t max_size, unsigned seed) {
  std::vector<uint32_t> words = words_of(data, size);
  const std::vector<size_t> starts = instructions_of(words);
  std::minstd_rand rng(seed);
  auto pick = [&](size_t below) { return below == 0 ? size_t(0) : size_t(rng() % below); };
  if (words.size() < 5 || words[0] != 0x07230203u || starts.empty() || pick(5) == 0)
    return LLVMFuzzerMutate(data, size, max_size);
  const uint32_t bound = words[3];
  const size_t at = starts[pick(starts.size())];
  const uint32_t count = words[at] >> 16, opcode = words[at] & 0xFFFFu;
  switch (pick(6)) {
    case 0:
    case 1: {  // an operand: another instruction's result id, an undefined id, the bound, 0, anything
      if (count < 2) break;
      const size_t other = starts[pick(starts.size())];
      const uint32_t values[] = {(words[other] >> 16) > 2 ? words[other + 2] : 1u,
                                 (words[other] >> 16) > 1 ? words[other + 1] : 1u,
                                 bound - 1,
                                 bound,
                                 0,
                                 uint32_t(rng())};
      words[at + 1 + pick(count - 1)] = values[pick(std::size(values))];
      break;
    }
    case 2: {  // a decoration's or capability's number, or an execution mode's (the word count may lie)
      const size_t word = opcode == 71 || opcode == 16 ? 2 : 1;
      if ((opcode == 71 || opcode == 17 || opcode == 16) && count > word)
        words[at + word] = uint32_t(pick(64));
      else if (count >= 2)
        words[at + 1] ^= 1u << pick(32);
      break;
    }
    case 3:  // drop the instruction
      words.erase(words.begin() + long(at), words.begin() + long(at + count));
      break;
    case 4:  // duplicate it, or move it after its neighbour
      if (pick(2) && (words.size() + count) * 4 <= max_size) {
        std::vector<uint32_t> copy(words.begin() + long(at), words.begin() + long(at + count));
        words.insert(words.begin() + long(at), copy.begin(), copy.end());
      } else if (at + count < words.size() && (words[at + count] >> 16) != 0 &&
                 (words[at + count] >> 16) <= words.size() - at - count) {
        std::rotate(words.begin() + long(at), words.begin() + long(at + count),
                    words.begin() + long(at + count + (words[at + count] >> 16)));
      }
      break;
    default:  // another word count
      words[at] = (uint32_t(std::max<int64_t>(1, int64_t(count) + (pick(2) ? 1 : -1))) << 16) | opcode;
      break;
  }
  const size_t bytes = std::min(words.size() * 4, max_size & ~size_t(3));
  std::memcpy(data, words.data(), bytes);
  return bytes;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::vector<uint32_t> words = words_of(data, size);
  (void)statepack::spirv::walk(words);
  return 0;
}
