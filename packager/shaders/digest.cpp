#include "digest.hpp"

#include <nettle/hmac.h>
#include <nettle/memops.h>
#include <nettle/sha2.h>
#include <nettle/version.h>

namespace statepack::packager {

namespace {
// Nettle 4 dropped the digest functions' length argument (always the whole digest here).
#if NETTLE_VERSION_MAJOR >= 4
void digest_into(sha256_ctx& state, Digest& out) {
  sha256_digest(&state, out.data());
}
void digest_into(hmac_sha256_ctx& state, Digest& out) {
  hmac_sha256_digest(&state, out.data());
}
#else
void digest_into(sha256_ctx& state, Digest& out) {
  sha256_digest(&state, out.size(), out.data());
}
void digest_into(hmac_sha256_ctx& state, Digest& out) {
  hmac_sha256_digest(&state, out.size(), out.data());
}
#endif
}  // namespace

// Nettle rather than OpenSSL's libcrypto: the same SHA-256 (with the CPU's SHA extensions where there are
// any), without OpenSSL's start-up (its configuration file and provider looked up at the first hash,
// ~3 ms of every pack, a repack of nothing changed included).
struct Sha256::Context {
  sha256_ctx state;
};

Sha256::Sha256() : context_(std::make_unique<Context>()) {
  sha256_init(&context_->state);
}

Sha256::~Sha256() = default;

Sha256& Sha256::update(std::span<const uint8_t> bytes) {
  sha256_update(&context_->state, bytes.size(), bytes.data());
  return *this;
}

Digest Sha256::finish() {
  Digest out{};
  digest_into(context_->state, out);
  return out;
}

Digest sha256(std::span<const uint8_t> bytes) {
  sha256_ctx state;
  sha256_init(&state);
  sha256_update(&state, bytes.size(), bytes.data());
  Digest out{};
  digest_into(state, out);
  return out;
}

Digest hmac_sha256(std::span<const uint8_t> secret, std::span<const uint8_t> message) {
  hmac_sha256_ctx state;
  hmac_sha256_set_key(&state, secret.size(), secret.data());
  hmac_sha256_update(&state, message.size(), message.data());
  Digest out{};
  digest_into(state, out);
  return out;
}

bool same_digest(const Digest& a, const Digest& b) {
  return nettle_memeql_sec(a.data(), b.data(), a.size()) != 0;
}

}  // namespace statepack::packager
