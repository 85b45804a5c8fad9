// The compile cache's building blocks, shared by its entries and by a pack's archive record
// (pack/archive_reuse.hpp): keys built from typed fields, and little-endian payloads read with bounds.
#pragma once

#include <cstdint>
#include <cstring>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "digest.hpp"

namespace statepack::packager {

using CacheKey = Digest;

// Builds a key from typed fields, each length-prefixed so that no two field lists hash alike. SHA-256: a
// shared cache is written by other machines, and no one may construct two inputs with one key.
class KeyBuilder {
 public:
  KeyBuilder& add(std::string_view text) {
    add(uint64_t(text.size()));
    hash_.update(text);
    return *this;
  }
  KeyBuilder& add(uint64_t value) {
    uint8_t bytes[8];
    for (int i = 0; i < 8; ++i) bytes[i] = uint8_t(value >> (8 * i));
    hash_.update(bytes);
    return *this;
  }
  KeyBuilder& add(const Digest& key) {
    hash_.update(key);
    return *this;
  }
  KeyBuilder& add(const std::vector<uint32_t>& words) {
    add(uint64_t(words.size()));
    hash_.update({reinterpret_cast<const uint8_t*>(words.data()), words.size() * 4});
    return *this;
  }
  CacheKey key() { return hash_.finish(); }

 private:
  Sha256 hash_;
};

// Little-endian payload writing and bounded reading.
class PayloadWriter {
 public:
  void u32(uint32_t v) {
    for (int i = 0; i < 4; ++i) bytes.push_back(uint8_t(v >> (8 * i)));
  }
  void u64(uint64_t v) {
    u32(uint32_t(v));
    u32(uint32_t(v >> 32));
  }
  void str(std::string_view s) {
    u32(uint32_t(s.size()));
    bytes.insert(bytes.end(), s.begin(), s.end());
  }
  void words(const std::vector<uint32_t>& w) {
    u32(uint32_t(w.size()));
    for (uint32_t v : w) u32(v);
  }
  std::vector<uint8_t> bytes;
};

class PayloadReader {
 public:
  explicit PayloadReader(std::span<const uint8_t> bytes) : bytes_(bytes) {}
  bool u32(uint32_t& v) {
    if (bytes_.size() - at_ < 4) return false;
    v = 0;
    for (int i = 0; i < 4; ++i) v |= uint32_t(bytes_[at_ + size_t(i)]) << (8 * i);
    at_ += 4;
    return true;
  }
  bool u64(uint64_t& v) {
    uint32_t low = 0, high = 0;
    if (!u32(low) || !u32(high)) return false;
    v = uint64_t(high) << 32 | low;
    return true;
  }
  bool str(std::string& s) {
    uint32_t n = 0;
    if (!u32(n) || bytes_.size() - at_ < n) return false;
    s.assign(reinterpret_cast<const char*>(bytes_.data() + at_), n);
    at_ += n;
    return true;
  }
  // Whether `count` items of at least `bytes` each can still follow: a count read from an entry is
  // checked against what is left before anything is sized by it.
  bool room_for(uint64_t count, size_t bytes) const { return count <= (bytes_.size() - at_) / bytes; }
  bool raw(uint8_t* out, size_t n) {
    if (bytes_.size() - at_ < n) return false;
    std::memcpy(out, bytes_.data() + at_, n);
    at_ += n;
    return true;
  }
  bool words(std::vector<uint32_t>& w) {
    uint32_t n = 0;
    if (!u32(n) || (bytes_.size() - at_) / 4 < n) return false;
    w.resize(n);
    for (uint32_t& v : w) u32(v);
    return true;
  }
  bool done() const { return at_ == bytes_.size(); }
  size_t left() const { return bytes_.size() - at_; }

 private:
  std::span<const uint8_t> bytes_;
  size_t at_ = 0;
};

}  // namespace statepack::packager
