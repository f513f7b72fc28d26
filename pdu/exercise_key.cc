#include "pdu/exercise_key.h"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <iterator>
#include <stdexcept>

#include <fmt/format.h>
#include <sodium.h>

namespace dt {

struct ExerciseKey::State {
  // HMAC state right after the key pads: copied for every MAC, never updated itself.
  crypto_auth_hmacsha512256_state keyed;
};

ExerciseKey::ExerciseKey(std::span<const uint8_t> key)
    : state_(std::make_unique<State>()), size_(key.size()) {
  if (key.size() < kMinExerciseKeyBytes || key.size() > kMaxExerciseKeyBytes) {
    throw std::invalid_argument(fmt::format("an exercise key of {} bytes: it needs {} to {} bytes",
                                            key.size(), kMinExerciseKeyBytes,
                                            kMaxExerciseKeyBytes));
  }
  if (sodium_init() < 0) throw std::runtime_error("libsodium could not be initialised");
  crypto_auth_hmacsha512256_init(&state_->keyed, key.data(), key.size());
}

ExerciseKey::~ExerciseKey() { sodium_memzero(state_.get(), sizeof(State)); }

std::shared_ptr<const ExerciseKey> ExerciseKey::FromFile(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    throw std::invalid_argument(fmt::format("cannot read the exercise key file {}: {}",
                                            path.string(), std::strerror(errno)));
  }
  // One byte more than the maximum is enough to tell the file is too long.
  std::vector<uint8_t> bytes(kMaxExerciseKeyBytes + 1);
  in.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  if (in.bad()) {
    throw std::invalid_argument(
        fmt::format("cannot read the exercise key file {}: read error", path.string()));
  }
  bytes.resize(static_cast<size_t>(in.gcount()));
  const size_t n = bytes.size();
  if (n < kMinExerciseKeyBytes || n > kMaxExerciseKeyBytes) {
    sodium_memzero(bytes.data(), bytes.size());
    throw std::invalid_argument(fmt::format(
        "the exercise key file {} holds {}{} bytes; a key is {} to {} raw bytes (make one: "
        "head -c 32 /dev/urandom > {})",
        path.string(), n > kMaxExerciseKeyBytes ? "more than " : "",
        n > kMaxExerciseKeyBytes ? kMaxExerciseKeyBytes : n, kMinExerciseKeyBytes,
        kMaxExerciseKeyBytes, path.string()));
  }
  auto key = std::make_shared<const ExerciseKey>(bytes);
  sodium_memzero(bytes.data(), bytes.size());
  return key;
}

Mac ExerciseKey::Compute(std::span<const uint8_t> a, std::span<const uint8_t> b) const {
  crypto_auth_hmacsha512256_state s = state_->keyed;
  crypto_auth_hmacsha512256_update(&s, a.data(), a.size());
  crypto_auth_hmacsha512256_update(&s, b.data(), b.size());
  Mac mac;
  crypto_auth_hmacsha512256_final(&s, mac.data());
  sodium_memzero(&s, sizeof s);
  return mac;
}

bool ExerciseKey::Verify(std::span<const uint8_t> a, std::span<const uint8_t> b,
                         std::span<const uint8_t> mac) const {
  if (mac.size() != kMacBytes) return false;
  const Mac want = Compute(a, b);
  return crypto_verify_32(want.data(), mac.data()) == 0;
}

}  // namespace dt
