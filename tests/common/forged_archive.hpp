// Forging archives for hostile-input tests: re-encode edited contents, or edit bytes and re-seal them
// (blob content hashes and the whole-file checksum recomputed), as an attacker who knows the format
// would. Either way the result passes the checksum, so only the reader's own checks stand in the way.
#pragma once

#include <cstdint>
#include <cstring>
#include <span>
#include <vector>

#include "format/archive_format.hpp"

namespace statepack::testing {

// Archive bytes in 4-byte aligned memory, as from_memory needs.
struct ForgedBytes {
  std::vector<uint32_t> words;
  size_t size = 0;
  ForgedBytes() = default;
  explicit ForgedBytes(const std::vector<uint8_t>& bytes)
      : words((bytes.size() + 3) / 4), size(bytes.size()) {
    if (!bytes.empty()) std::memcpy(words.data(), bytes.data(), bytes.size());
  }
  std::span<const uint8_t> span() const { return {reinterpret_cast<const uint8_t*>(words.data()), size}; }
};

inline uint32_t get_u32(const std::vector<uint8_t>& b, size_t at) {
  return uint32_t(b[at]) | uint32_t(b[at + 1]) << 8 | uint32_t(b[at + 2]) << 16 | uint32_t(b[at + 3]) << 24;
}
inline void put_u32(std::vector<uint8_t>& b, size_t at, uint32_t v) {
  for (int i = 0; i < 4; ++i) b[at + i] = uint8_t(v >> (8 * i));
}
inline void put_u64(std::vector<uint8_t>& b, size_t at, uint64_t v) {
  for (int i = 0; i < 8; ++i) b[at + i] = uint8_t(v >> (8 * i));
}

struct SectionEntry {
  uint32_t tag = 0, offset = 0, size = 0, count = 0;
};
constexpr uint32_t tag_of(const char (&s)[5]) {
  return uint32_t(uint8_t(s[0])) | uint32_t(uint8_t(s[1])) << 8 | uint32_t(uint8_t(s[2])) << 16 |
         uint32_t(uint8_t(s[3])) << 24;
}

// The section table of (well-formed) archive bytes.
inline std::vector<SectionEntry> sections_of(const std::vector<uint8_t>& b) {
  std::vector<SectionEntry> out;
  if (b.size() < 64) return out;
  const uint32_t count = get_u32(b, 48), table = get_u32(b, 52);
  for (uint64_t i = 0; i < count && table + 16 * (i + 1) <= b.size(); ++i) {
    const size_t e = table + 16 * i;
    out.push_back({get_u32(b, e), get_u32(b, e + 4), get_u32(b, e + 8), get_u32(b, e + 12)});
  }
  return out;
}

// Recomputes every blob content hash the BLOB table can locate, then the whole-file checksum.
inline void reseal(std::vector<uint8_t>& b) {
  if (b.size() < 64) return;
  for (const SectionEntry& s : sections_of(b)) {
    if (s.tag != tag_of("BLOB") || uint64_t(s.offset) + s.size > b.size()) continue;
    for (uint32_t i = 0; i + 16 <= s.size; i += 16) {
      const uint32_t offset = get_u32(b, s.offset + i), size = get_u32(b, s.offset + i + 4);
      if (uint64_t(offset) + size <= b.size())
        put_u64(b, s.offset + i + 8, format::hash_bytes({b.data() + offset, size}));
    }
  }
  put_u64(b, 40, 0);
  put_u64(b, 40, format::hash_bytes(b));
}

}  // namespace statepack::testing
