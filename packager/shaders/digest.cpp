#include "digest.hpp"

#include <openssl/crypto.h>
#include <openssl/evp.h>
#include <openssl/hmac.h>

#include <stdexcept>

namespace statepack::packager {

namespace {
// SHA-256 fetched from OpenSSL's provider once (EVP_sha256() looks it up again at every use).
const EVP_MD* sha256_md() {
  static EVP_MD* const md = EVP_MD_fetch(nullptr, "SHA256", nullptr);
  if (!md) throw std::runtime_error("OpenSSL: SHA-256 is not available");
  return md;
}
}  // namespace

struct Sha256::Context {
  EVP_MD_CTX* md = nullptr;
};

Sha256::Sha256() : context_(std::make_unique<Context>()) {
  context_->md = EVP_MD_CTX_new();
  if (!context_->md || EVP_DigestInit_ex(context_->md, sha256_md(), nullptr) != 1)
    throw std::runtime_error("OpenSSL: SHA-256 is not available");
}

Sha256::~Sha256() {
  if (context_) EVP_MD_CTX_free(context_->md);
}

Sha256& Sha256::update(std::span<const uint8_t> bytes) {
  EVP_DigestUpdate(context_->md, bytes.data(), bytes.size());
  return *this;
}

Digest Sha256::finish() {
  Digest out{};
  unsigned int size = 0;
  EVP_DigestFinal_ex(context_->md, out.data(), &size);
  return out;
}

Digest sha256(std::span<const uint8_t> bytes) {
  Digest out{};
  unsigned int size = 0;
  if (EVP_Digest(bytes.data(), bytes.size(), out.data(), &size, sha256_md(), nullptr) != 1)
    throw std::runtime_error("OpenSSL: SHA-256 is not available");
  return out;
}

Digest hmac_sha256(std::span<const uint8_t> secret, std::span<const uint8_t> message) {
  Digest out{};
  unsigned int size = 0;
  if (!HMAC(EVP_sha256(), secret.data(), int(secret.size()), message.data(), message.size(), out.data(),
            &size))
    throw std::runtime_error("OpenSSL: HMAC-SHA-256 is not available");
  return out;
}

bool same_digest(const Digest& a, const Digest& b) {
  return CRYPTO_memcmp(a.data(), b.data(), a.size()) == 0;
}

}  // namespace statepack::packager
