// Tests ExerciseKey (key files; the keyed BLAKE2b-256 MAC and its key derivation against
// libsodium's one-shot calls and Python's hashlib) and the authentication trailer's byte layout.
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

// The documented construction, spelled out with libsodium's one-shot calls: the MAC key is the
// personalised BLAKE2b-512 of the key file's bytes, the MAC keyed BLAKE2b-256 under it.
Mac ByTheDocumentation(const std::vector<uint8_t>& key_file, const std::vector<uint8_t>& message) {
  const std::array<uint8_t, 16> salt{};
  std::array<uint8_t, 16> person;
  std::copy(kMacKeyPerson.begin(), kMacKeyPerson.end(), person.begin());
  std::array<uint8_t, kMacKeyBytes> mac_key;
  EXPECT_EQ(crypto_generichash_blake2b_salt_personal(mac_key.data(), mac_key.size(),
                                                     key_file.data(), key_file.size(), nullptr, 0,
                                                     salt.data(), person.data()),
            0);
  Mac mac;
  EXPECT_EQ(crypto_generichash_blake2b(mac.data(), mac.size(), message.data(), message.size(),
                                       mac_key.data(), mac_key.size()),
            0);
  return mac;
}

TEST(ExerciseKey, IsKeyedBlake2bUnderTheDerivedKey) {
  ASSERT_GE(sodium_init(), 0);
  for (const size_t n : {kMinExerciseKeyBytes, size_t{64}, size_t{65}, kMaxExerciseKeyBytes}) {
    std::vector<uint8_t> k(n);
    std::iota(k.begin(), k.end(), uint8_t{1});
    const ExerciseKey key(k);
    const auto message = Bytes("the LCM bytes of a PDU and its trailer");
    const Mac want = ByTheDocumentation(k, message);
    EXPECT_EQ(key.Compute(message), want) << n << "-byte key file";
    EXPECT_TRUE(key.Verify(message, want));
    Mac bad = want;
    bad[31] ^= 1;
    EXPECT_FALSE(key.Verify(message, bad));
    EXPECT_FALSE(key.Verify(message, std::span<const uint8_t>(want).first(31)));
    auto changed = message;
    changed[0] ^= 1;
    EXPECT_FALSE(key.Verify(changed, want));
    // The derivation reads the whole file: one byte more gives another key.
    k.push_back(0);
    if (k.size() <= kMaxExerciseKeyBytes) {
      EXPECT_NE(ExerciseKey(k).Compute(message), want);
    }
  }
}

// Values computed with Python's hashlib, an implementation independent of libsodium, as a holder
// of the key outside this code would (transport/test/verify_mac_with_python.py does it on a
// capture):
//   mac_key = hashlib.blake2b(key_file, digest_size=64, person=b"dt-pdu-mac-key-1").digest()
//   hashlib.blake2b(message, key=mac_key, digest_size=32).digest()
TEST(ExerciseKey, MatchesPythonHashlib) {
  std::vector<uint8_t> k(32);
  std::iota(k.begin(), k.end(), uint8_t{1});
  const Mac want32 = {0xcb, 0xcf, 0x5f, 0xcd, 0x20, 0xcb, 0x2b, 0xba, 0xe9, 0x94, 0x68,
                      0x71, 0x8a, 0x51, 0xd9, 0x0a, 0xcd, 0x02, 0x23, 0x70, 0x31, 0xb1,
                      0x93, 0xbb, 0xef, 0x65, 0x28, 0x17, 0xdd, 0x0a, 0xcb, 0xfa};
  // The message as the Python side wrote it: b"the LCM bytes of a PDU" + b"and its trailer".
  EXPECT_EQ(ExerciseKey(k).Compute(Bytes("the LCM bytes of a PDUand its trailer")), want32);
  const std::vector<uint8_t> longest(kMaxExerciseKeyBytes, 0xaa);
  const Mac want1024 = {0x56, 0x0e, 0xf5, 0xf4, 0x37, 0x98, 0x3e, 0x05, 0x99, 0xea, 0xf2,
                        0x85, 0x16, 0x31, 0xbd, 0xcb, 0xe5, 0x02, 0x11, 0x5e, 0x47, 0x39,
                        0x1b, 0x8d, 0x17, 0x98, 0x61, 0xc9, 0xda, 0xf0, 0xce, 0xe9};
  EXPECT_EQ(ExerciseKey(longest).Compute(Bytes("a key file of the largest length")), want1024);
}

// The former MAC, HMAC-SHA512-256 of the same bytes under the raw key, is not accepted.
TEST(ExerciseKey, RefusesTheFormerHmacSha512256) {
  ASSERT_GE(sodium_init(), 0);
  std::vector<uint8_t> k(crypto_auth_KEYBYTES);
  std::iota(k.begin(), k.end(), uint8_t{1});
  const auto message = Bytes("the LCM bytes of a PDU and its trailer");
  Mac hmac;
  crypto_auth(hmac.data(), message.data(), message.size(), k.data());
  EXPECT_FALSE(ExerciseKey(k).Verify(message, hmac));
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
      'D', 'T', 'A', '2', 0x01, 0x02, 0xA0, 0xB0, 0x11, 0x22, 0x33, 0x44, 0x55, 0x66, 0x77, 0x88,
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
  bytes[8 + 3] = '1';  // the former trailer version (HMAC-SHA512-256)
  EXPECT_FALSE(ParseTrailer(bytes).has_value());
  bytes[8 + 3] = '3';  // a later one
  EXPECT_FALSE(ParseTrailer(bytes).has_value());
  EXPECT_FALSE(ParseTrailer({}).has_value());
}

}  // namespace
}  // namespace dt
