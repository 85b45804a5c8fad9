// The cache's keys and signatures are the standard SHA-256 and HMAC-SHA-256, whichever library computes
// them: a cache written by one statepack build (or another machine's) must be read by the next. Known
// answers from FIPS 180-4's examples and RFC 4231.
#include <gtest/gtest.h>

#include <string>

#include "shaders/digest.hpp"

namespace statepack::packager {
namespace {

std::string hex(const Digest& d) {
  static const char* digits = "0123456789abcdef";
  std::string out;
  for (uint8_t b : d) out += {digits[b >> 4], digits[b & 15]};
  return out;
}

std::span<const uint8_t> bytes(std::string_view text) {
  return {reinterpret_cast<const uint8_t*>(text.data()), text.size()};
}

TEST(DigestTest, Sha256GivesTheStandardsAnswers) {
  EXPECT_EQ(hex(sha256(std::string_view("abc"))),
            "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  EXPECT_EQ(hex(sha256(std::string_view(""))),
            "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  EXPECT_EQ(hex(sha256(std::string_view("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq"))),
            "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
  // 112 bytes fed in pieces that straddle the 64-byte block: the same as in one piece.
  const std::string two_blocks =
      "abcdefghbcdefghicdefghijdefghijkefghijklfghijklmghijklmnhijklmnoijklmnopjklmnopqklmnopqrlmnopqrsmnopqr"
      "s"
      "tnopqrstu";
  const char* expected = "cf5b16a778af8380036ce59e7b0492370b249b11e8f07a51afac45037afee9d1";
  EXPECT_EQ(hex(sha256(std::string_view(two_blocks))), expected);
  Sha256 pieces;
  const std::string_view text(two_blocks);
  pieces.update(text.substr(0, 7)).update(text.substr(7, 60)).update(text.substr(67));
  EXPECT_EQ(hex(pieces.finish()), expected);
}

TEST(DigestTest, HmacSha256GivesRfc4231sAnswers) {
  EXPECT_EQ(hex(hmac_sha256(bytes("Jefe"), bytes("what do ya want for nothing?"))),
            "5bdcc146bf60754e6a042426089575c75a003f089d2739839dec58b964ec3843");
  // A key longer than the block is hashed first (test case 6).
  const std::string long_key(131, '\xaa');
  EXPECT_EQ(
      hex(hmac_sha256(bytes(long_key), bytes("Test Using Larger Than Block-Size Key - Hash Key First"))),
      "60e431591ee0b67f0d8a26aacbf5b77f8e0bc6213728c5140546040f0ee37f54");
}

TEST(DigestTest, SameDigestComparesEveryByte) {
  const Digest a = sha256(std::string_view("a"));
  Digest b = a;
  EXPECT_TRUE(same_digest(a, b));
  for (size_t i : {size_t{0}, size_t{17}, size_t{31}}) {
    b = a;
    b[i] ^= 1;
    EXPECT_FALSE(same_digest(a, b)) << i;
  }
}

}  // namespace
}  // namespace statepack::packager
