#include "core/sha256.hpp"

#include <gtest/gtest.h>

namespace hrisim::core {
namespace {

// Test vectors from FIPS 180-4's examples (NIST CSRC).
TEST(Sha256, KnownVectors) {
  EXPECT_EQ(sha256_hex(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  EXPECT_EQ(sha256_hex("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  EXPECT_EQ(sha256_hex("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq"),
            "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
  EXPECT_EQ(sha256_hex(std::string(1'000'000, 'a')),
            "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
}

// Lengths around the 55/56/64-byte padding boundaries, fed in pieces, equal the one-shot hash.
TEST(Sha256, IncrementalEqualsOneShot) {
  for (std::size_t length : {0u, 1u, 55u, 56u, 57u, 63u, 64u, 65u, 119u, 120u, 200u}) {
    std::string text;
    for (std::size_t i = 0; i < length; ++i) text += static_cast<char>('a' + i % 26);
    for (std::size_t piece : {1u, 7u, 64u}) {
      Sha256 hash;
      for (std::size_t at = 0; at < text.size(); at += piece) hash.update(std::string_view(text).substr(at, piece));
      EXPECT_EQ(to_hex(hash.digest()), sha256_hex(text)) << "length " << length << " piece " << piece;
    }
  }
}

TEST(Sha256, DiffersOnOneBit) { EXPECT_NE(sha256_hex("scenario-a"), sha256_hex("scenario-b")); }

}  // namespace
}  // namespace hrisim::core
