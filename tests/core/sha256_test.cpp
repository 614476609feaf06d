// Sha256: the FIPS 180-2 test vectors, in one piece and in chunks, and the digest syntax check.
#include "isocorr/util/sha256.h"

#include <gtest/gtest.h>

#include <string>

namespace isocorr {
namespace {

std::string digest_of(const std::string& bytes) {
  Sha256 hasher;
  hasher.update(bytes);
  return hasher.hex_digest();
}

TEST(Sha256, MatchesKnownDigests) {
  EXPECT_EQ(digest_of(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  EXPECT_EQ(digest_of("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
}

TEST(Sha256, ChunkedUpdatesEqualOneUpdate) {
  const std::string text = "abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq";
  Sha256 hasher;
  for (size_t at = 0; at < text.size(); at += 7) hasher.update(std::string_view(text).substr(at, 7));
  EXPECT_EQ(hasher.hex_digest(), "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
}

TEST(Sha256, RecognisesHexDigests) {
  EXPECT_TRUE(is_sha256_hex(digest_of("abc")));
  EXPECT_FALSE(is_sha256_hex(""));
  EXPECT_FALSE(is_sha256_hex(std::string(63, 'a')));
  EXPECT_FALSE(is_sha256_hex(std::string(64, 'A')));
  EXPECT_FALSE(is_sha256_hex(std::string(64, 'g')));
}

}  // namespace
}  // namespace isocorr
