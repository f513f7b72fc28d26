// Tests ExerciseKey (key files, HMAC-SHA512-256 against libsodium and RFC 4231) and the
// authentication trailer's byte layout.
#include "pdu/exercise_key.h"

#include <gtest/gtest.h>
#include <sodium.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <numeric>
#include <stdexcept>
#include <string>

#include "pdu/auth_trailer.h"

namespace dt {
namespace {

std::vector<uint8_t> Bytes(std::string_view s) { return {s.begin(), s.end()}; }

std::string ErrorOf(const std::filesystem::path& path) {
  try {
    ExerciseKey::FromFile(path);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

class KeyFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() / ("dt-key-" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::filesystem::path Write(const std::string& name, size_t n) {
    const auto path = dir_ / name;
    std::ofstream out(path, std::ios::binary);
    for (size_t i = 0; i < n; ++i) out.put(static_cast<char>(i * 7 + 1));
    return path;
  }
  std::filesystem::path dir_;
};

TEST_F(KeyFiles, ReadsAKeyOf32Bytes) {
  const auto key = ExerciseKey::FromFile(Write("good.key", 32));
  ASSERT_NE(key, nullptr);
  EXPECT_EQ(key->size(), 32u);
}

TEST_F(KeyFiles, AMissingFileNamesThePath) {
  const std::string e = ErrorOf(dir_ / "absent.key");
  EXPECT_NE(e.find((dir_ / "absent.key").string()), std::string::npos) << e;
  EXPECT_NE(e.find("No such file"), std::string::npos) << e;
}

TEST_F(KeyFiles, AShortKeyNamesThePathAndLength) {
  const auto path = Write("short.key", 31);
  const std::string e = ErrorOf(path);
  EXPECT_NE(e.find(path.string()), std::string::npos) << e;
  EXPECT_NE(e.find("holds 31 bytes"), std::string::npos) << e;
  EXPECT_NE(e.find("head -c 32 /dev/urandom"), std::string::npos) << e;
  EXPECT_NE(ErrorOf(Write("empty.key", 0)).find("holds 0 bytes"), std::string::npos);
}

TEST_F(KeyFiles, RefusesAFileTooLongToBeAKey) {
  const std::string e = ErrorOf(Write("long.key", kMaxExerciseKeyBytes + 1));
  EXPECT_NE(e.find("more than 1024 bytes"), std::string::npos) << e;
  EXPECT_NO_THROW(ExerciseKey::FromFile(Write("max.key", kMaxExerciseKeyBytes)));
}

TEST_F(KeyFiles, RefusesADirectory) {
  const std::string e = ErrorOf(dir_);
  EXPECT_NE(e.find(dir_.string()), std::string::npos) << e;
}

TEST(ExerciseKey, RefusesShortKeysInMemory) {
  const std::vector<uint8_t> k(31, 1);
  EXPECT_THROW(ExerciseKey{k}, std::invalid_argument);
}

TEST(ExerciseKey, MatchesLibsodiumCryptoAuthFor32ByteKeys) {
  ASSERT_GE(sodium_init(), 0);
  std::vector<uint8_t> k(crypto_auth_KEYBYTES);
  std::iota(k.begin(), k.end(), uint8_t{1});
  const ExerciseKey key(k);
  const auto a = Bytes("the LCM bytes of a PDU");
  const auto b = Bytes("and its trailer");
  std::vector<uint8_t> whole = a;
  whole.insert(whole.end(), b.begin(), b.end());
  Mac want;
  crypto_auth(want.data(), whole.data(), whole.size(), k.data());
  EXPECT_EQ(key.Compute(a, b), want);
  EXPECT_TRUE(key.Verify(a, b, want));
  Mac bad = want;
  bad[31] ^= 1;
  EXPECT_FALSE(key.Verify(a, b, bad));
  EXPECT_FALSE(key.Verify(b, a, want));  // the MAC covers the order too
  EXPECT_FALSE(key.Verify(a, b, std::span<const uint8_t>(want).first(31)));
}

// RFC 4231 test case 6 (a 131-byte key, hashed first): HMAC-SHA-512's first 32 bytes.
TEST(ExerciseKey, MatchesRfc4231ForALongKey) {
  const std::vector<uint8_t> k(131, 0xaa);
  const ExerciseKey key(k);
  const Mac mac =
      key.Compute(Bytes("Test Using Larger Than Block-Size Key - "), Bytes("Hash Key First"));
  const Mac want = {0x80, 0xb2, 0x42, 0x63, 0xc7, 0xc1, 0xa3, 0xeb, 0xb7, 0x14, 0x93,
                    0xc1, 0xdd, 0x7b, 0xe8, 0xb4, 0x9b, 0x46, 0xd1, 0xf4, 0x1b, 0x4a,
                    0xee, 0xc1, 0x12, 0x1b, 0x01, 0x37, 0x83, 0xf8, 0xf3, 0x52};
  EXPECT_EQ(mac, want);
}

TEST(AuthTrailer, LayoutIsBigEndianAtTheDocumentedOffsets) {
  AuthTrailer t;
  t.sender = {0x0102, 0xA0B0};
  t.incarnation = 0x1122334455667788ull;
  t.sequence = 0x0000000000000203ull;
  t.send_time_ms = 0x0000018F00000001ull;
  for (size_t i = 0; i < kMacBytes; ++i) t.mac[i] = static_cast<uint8_t>(0xC0 + i);
  std::vector<uint8_t> bytes(8, 0xEE);  // stands for a PDU
  AppendTrailer(t, bytes);
  ASSERT_EQ(bytes.size(), 8 + kAuthTrailerBytes);
  ASSERT_EQ(kAuthTrailerBytes, 64u);
  const std::vector<uint8_t> head(bytes.begin() + 8, bytes.begin() + 8 + 32);
  const std::vector<uint8_t> want = {
      'D', 'T', 'A', '1', 0x01, 0x02, 0xA0, 0xB0, 0x11, 0x22, 0x33, 0x44, 0x55, 0x66, 0x77, 0x88,
      0,   0,   0,   0,   0,    0,    0x02, 0x03, 0,    0,    0x01, 0x8F, 0,    0,    0,    0x01};
  EXPECT_EQ(head, want);
  EXPECT_EQ(bytes[8 + 32], 0xC0);
  EXPECT_EQ(bytes.back(), 0xC0 + 31);

  const auto parsed = ParseTrailer(bytes);
  ASSERT_TRUE(parsed.has_value());
  EXPECT_EQ(parsed->sender, t.sender);
  EXPECT_EQ(parsed->incarnation, t.incarnation);
  EXPECT_EQ(parsed->sequence, t.sequence);
  EXPECT_EQ(parsed->send_time_ms, t.send_time_ms);
  EXPECT_EQ(parsed->mac, t.mac);
}

TEST(AuthTrailer, ParseRefusesShortBytesAndAMissingMagic) {
  AuthTrailer t;
  std::vector<uint8_t> bytes(8, 0);
  AppendTrailer(t, bytes);
  EXPECT_TRUE(ParseTrailer(bytes).has_value());
  EXPECT_FALSE(ParseTrailer(std::span<const uint8_t>(bytes).subspan(1)).has_value());
  bytes[8 + 3] = '2';  // another trailer version
  EXPECT_FALSE(ParseTrailer(bytes).has_value());
  EXPECT_FALSE(ParseTrailer({}).has_value());
}

}  // namespace
}  // namespace dt
