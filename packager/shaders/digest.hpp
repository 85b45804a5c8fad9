// SHA-256 and HMAC-SHA-256 (Nettle): the compile cache's keys, entry checks and signatures.
// A cache shared by a team is written by other machines, so its keys must be a hash whose collisions
// cannot be constructed (a fast non-cryptographic hash such as XXH3 does not promise that).
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <string_view>

namespace statepack::packager {

using Digest = std::array<uint8_t, 32>;

// An incremental SHA-256.
class Sha256 {
 public:
  Sha256();
  ~Sha256();
  Sha256(const Sha256&) = delete;
  Sha256& operator=(const Sha256&) = delete;
  Sha256& update(std::span<const uint8_t> bytes);
  Sha256& update(std::string_view text) {
    return update({reinterpret_cast<const uint8_t*>(text.data()), text.size()});
  }
  Digest finish();

 private:
  struct Context;
  std::unique_ptr<Context> context_;
};

Digest sha256(std::span<const uint8_t> bytes);
inline Digest sha256(std::string_view text) {
  return sha256({reinterpret_cast<const uint8_t*>(text.data()), text.size()});
}

// HMAC-SHA-256 of `message` under `secret`.
Digest hmac_sha256(std::span<const uint8_t> secret, std::span<const uint8_t> message);

// Compares two digests in time that does not depend on where they differ (signatures).
bool same_digest(const Digest& a, const Digest& b);

}  // namespace statepack::packager
