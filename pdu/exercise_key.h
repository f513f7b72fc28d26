// ExerciseKey: the secret every process of an exercise shares to authenticate its PDUs.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <span>
#include <vector>

namespace dt {

// A key file holds the raw key bytes, nothing else (no encoding, no newline): make one with
//   head -c 32 /dev/urandom > exercise.key
inline constexpr size_t kMinExerciseKeyBytes = 32;
// A bigger file is almost certainly not a key (a path mistaken for one, a log file).
inline constexpr size_t kMaxExerciseKeyBytes = 1024;
// HMAC-SHA512-256 (libsodium crypto_auth): HMAC-SHA-512 truncated to its first 32 bytes.
inline constexpr size_t kMacBytes = 32;
using Mac = std::array<uint8_t, kMacBytes>;

// Computes HMAC-SHA512-256 over the concatenation of byte ranges. The key's HMAC state after the
// key pads is computed once, so each MAC costs only the message's SHA-512 blocks (plus one for
// the outer hash); for a 32-byte key the result equals libsodium's crypto_auth. Immutable after
// construction, so one key may be shared by several buses and threads.
class ExerciseKey {
 public:
  // Throws std::invalid_argument naming the length if the key is shorter than
  // kMinExerciseKeyBytes or longer than kMaxExerciseKeyBytes.
  explicit ExerciseKey(std::span<const uint8_t> key);
  ~ExerciseKey();  // wipes the key material
  ExerciseKey(const ExerciseKey&) = delete;
  ExerciseKey& operator=(const ExerciseKey&) = delete;

  // Reads a key file. Throws std::invalid_argument naming the path and the reason: the file is
  // missing or unreadable, or holds fewer than kMinExerciseKeyBytes (or more than
  // kMaxExerciseKeyBytes) bytes, the length named.
  static std::shared_ptr<const ExerciseKey> FromFile(const std::filesystem::path& path);

  // MAC of a || b.
  Mac Compute(std::span<const uint8_t> a, std::span<const uint8_t> b) const;
  // True if `mac` is the MAC of a || b; compares in constant time.
  bool Verify(std::span<const uint8_t> a, std::span<const uint8_t> b,
              std::span<const uint8_t> mac) const;

  size_t size() const { return size_; }

 private:
  struct State;
  std::unique_ptr<State> state_;
  size_t size_;
};

}  // namespace dt
