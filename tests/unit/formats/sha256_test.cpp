#include <gtest/gtest.h>

#include <random>
#include <string>

#include "dmgplace/formats/error.hpp"
#include "dmgplace/formats/sha256.hpp"
#include "test_support.hpp"

using dmgplace::formats::Sha256;
using dmgplace::formats::sha256_hex;

TEST(Sha256, KnownVectorsFromFips180) {
  EXPECT_EQ(sha256_hex("", 0), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  EXPECT_EQ(sha256_hex("abc", 3), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  std::string two_blocks = "abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq";
  EXPECT_EQ(sha256_hex(two_blocks.data(), two_blocks.size()),
            "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
  std::string million(1000000, 'a');
  EXPECT_EQ(sha256_hex(million.data(), million.size()),
            "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
}

TEST(Sha256, IncrementalUpdatesMatchOneShotForAnySplit) {
  std::mt19937 rng(7);
  std::string data(1000, '\0');
  for (auto& c : data) c = char(rng());
  const std::string whole = sha256_hex(data.data(), data.size());
  for (int trial = 0; trial < 50; ++trial) {
    Sha256 h;
    std::size_t pos = 0;
    while (pos < data.size()) {
      std::size_t n = std::min<std::size_t>(data.size() - pos, rng() % 130);
      h.update(data.data() + pos, n);
      pos += n;
    }
    EXPECT_EQ(h.finish_hex(), whole);
  }
}

TEST(Sha256, FileHashMatchesBufferAndMissingFileNamesIt) {
  dmgplace::test::TempDir dir;
  dmgplace::test::write_text(dir / "x.txt", "abc");
  EXPECT_EQ(dmgplace::formats::sha256_file(dir / "x.txt"), sha256_hex("abc", 3));
  try {
    dmgplace::formats::sha256_file(dir / "missing.txt");
    FAIL() << "expected an error";
  } catch (const dmgplace::Error& e) {
    EXPECT_NE(std::string(e.what()).find("missing.txt"), std::string::npos);
  }
}
