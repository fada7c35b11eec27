#include "core/simulation/sha256.hpp"

#include <gtest/gtest.h>

namespace kessler {
namespace {

// FIPS 180-2 appendix B examples.
TEST(Sha256, KnownVectors) {
  Sha256 empty;
  EXPECT_EQ(empty.hex_digest(), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  Sha256 abc;
  abc.update("abc");
  EXPECT_EQ(abc.hex_digest(), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  Sha256 two_blocks;
  two_blocks.update("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq");
  EXPECT_EQ(two_blocks.hex_digest(), "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
  Sha256 million;
  std::string a(1000, 'a');
  for (int i = 0; i < 1000; ++i) million.update(a);
  EXPECT_EQ(million.hex_digest(), "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
}

TEST(Sha256, SavedStateContinuesTheSameDigest) {
  const std::string text = "the quick brown fox jumps over the lazy dog, again and again and again";
  Sha256 whole;
  whole.update(text);
  for (std::size_t cut = 0; cut <= text.size(); cut += 7) {
    Sha256 first;
    first.update(text.substr(0, cut));
    Sha256 second;
    ASSERT_TRUE(second.restore_state(first.save_state()));
    second.update(text.substr(cut));
    EXPECT_EQ(second.hex_digest(), whole.hex_digest()) << "cut at " << cut;
  }
  Sha256 bad;
  EXPECT_FALSE(bad.restore_state("short"));
}

// A checkpoint's bytes must not depend on how the events were cut into updates.
TEST(Sha256, SavedStateDependsOnlyOnTheBytesHashed) {
  const std::string text(200, 'k');
  for (std::size_t piece : {1, 8, 10, 63, 64, 65, 100}) {
    Sha256 whole;
    whole.update(text.substr(0, 150));
    Sha256 pieces;
    for (std::size_t at = 0; at < 150; at += piece) pieces.update(text.substr(at, std::min(piece, 150 - at)));
    EXPECT_EQ(pieces.save_state(), whole.save_state()) << "pieces of " << piece;
  }
}

}  // namespace
}  // namespace kessler
