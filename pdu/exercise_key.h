// ExerciseKey: the secret every process of an exercise shares to authenticate its PDUs.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <span>
#include <string_view>
#include <vector>

namespace dt {

// A key file holds the raw key bytes, nothing else (no encoding, no newline): make one with
//   head -c 32 /dev/urandom > exercise.key
inline constexpr size_t kMinExerciseKeyBytes = 32;
// A bigger file is almost certainly not a key (a path mistaken for one, a log file).
inline constexpr size_t kMaxExerciseKeyBytes = 1024;

// The MAC is keyed BLAKE2b with a 32-byte digest (libsodium crypto_generichash; Python's
// hashlib.blake2b(data, key=mac_key, digest_size=32)). BLAKE2b takes keys of at most 64 bytes,
// so the MAC key is derived from the key file's bytes, whatever their length:
//   mac_key = BLAKE2b-512(key file bytes, no key, salt 16 zero bytes, person kMacKeyPerson)
// (hashlib.blake2b(file_bytes, digest_size=64, person=b"dt-pdu-mac-key-1").digest()).
inline constexpr size_t kMacBytes = 32;
inline constexpr size_t kMacKeyBytes = 64;
inline constexpr std::string_view kMacKeyPerson = "dt-pdu-mac-key-1";
static_assert(kMacKeyPerson.size() == 16, "BLAKE2b's personalisation is 16 bytes");
using Mac = std::array<uint8_t, kMacBytes>;

// Computes the PDU MAC above. The BLAKE2b state right after keying is computed once and copied
// for each MAC, so a MAC costs the key block's compression and the message's. Immutable after
// construction, so one key may be shared by several buses and threads.
class ExerciseKey {
 public:
  // `key`: the key file's bytes. Throws std::invalid_argument naming the length if they are
  // fewer than kMinExerciseKeyBytes or more than kMaxExerciseKeyBytes.
  explicit ExerciseKey(std::span<const uint8_t> key);
  ~ExerciseKey();  // wipes the key material
  ExerciseKey(const ExerciseKey&) = delete;
  ExerciseKey& operator=(const ExerciseKey&) = delete;

  // Reads a key file. Throws std::invalid_argument naming the path and the reason: the file is
  // missing or unreadable, or holds fewer than kMinExerciseKeyBytes (or more than
  // kMaxExerciseKeyBytes) bytes, the length named.
  static std::shared_ptr<const ExerciseKey> FromFile(const std::filesystem::path& path);

  // MAC of `message`.
  Mac Compute(std::span<const uint8_t> message) const;
  // True if `mac` is the MAC of `message`; compares in constant time.
  bool Verify(std::span<const uint8_t> message, std::span<const uint8_t> mac) const;

  // Length of the key file's bytes (not of the derived MAC key).
  size_t size() const { return size_; }

 private:
  struct State;
  std::unique_ptr<State> state_;
  size_t size_;
};

}  // namespace dt
