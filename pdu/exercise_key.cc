#include "pdu/exercise_key.h"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <iterator>
#include <stdexcept>

#include <fmt/format.h>
#include <sodium.h>

#include "base/demand.h"

namespace dt {

// The crypto_generichash_blake2b names rather than crypto_generichash's (BLAKE2b today): the MAC
// is BLAKE2b by definition, whatever libsodium's generic hash may become.
static_assert(kMacBytes >= crypto_generichash_blake2b_BYTES_MIN &&
              kMacBytes <= crypto_generichash_blake2b_BYTES_MAX);
static_assert(kMacKeyBytes == crypto_generichash_blake2b_KEYBYTES_MAX);
static_assert(kMacKeyPerson.size() == crypto_generichash_blake2b_PERSONALBYTES);

struct ExerciseKey::State {
  // BLAKE2b state right after init with the MAC key: copied for every MAC, never updated itself.
  crypto_generichash_blake2b_state keyed;
};

ExerciseKey::ExerciseKey(std::span<const uint8_t> key)
    : state_(std::make_unique<State>()), size_(key.size()) {
  if (key.size() < kMinExerciseKeyBytes || key.size() > kMaxExerciseKeyBytes) {
    throw std::invalid_argument(fmt::format("an exercise key of {} bytes: it needs {} to {} bytes",
                                            key.size(), kMinExerciseKeyBytes,
                                            kMaxExerciseKeyBytes));
  }
  if (sodium_init() < 0) throw std::runtime_error("libsodium could not be initialised");
  const std::array<uint8_t, crypto_generichash_blake2b_SALTBYTES> salt{};
  std::array<uint8_t, crypto_generichash_blake2b_PERSONALBYTES> person;
  std::copy(kMacKeyPerson.begin(), kMacKeyPerson.end(), person.begin());
  std::array<uint8_t, kMacKeyBytes> mac_key;
  const bool keyed = crypto_generichash_blake2b_salt_personal(mac_key.data(), mac_key.size(),
                                                              key.data(), key.size(), nullptr, 0,
                                                              salt.data(), person.data()) == 0 &&
                     crypto_generichash_blake2b_init(&state_->keyed, mac_key.data(), mac_key.size(),
                                                     kMacBytes) == 0;
  sodium_memzero(mac_key.data(), mac_key.size());
  // Only lengths outside BLAKE2b's limits make these fail, and the static_asserts exclude them.
  DT_DEMAND(keyed);
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

Mac ExerciseKey::Compute(std::span<const uint8_t> message) const {
  crypto_generichash_blake2b_state s = state_->keyed;
  crypto_generichash_blake2b_update(&s, message.data(), message.size());
  Mac mac;
  crypto_generichash_blake2b_final(&s, mac.data(), mac.size());
  // final wipes the chaining value and the buffer (which held the key block); the rest of the
  // copy (counters, lengths) is not secret, so it is not wiped again.
  return mac;
}

bool ExerciseKey::Verify(std::span<const uint8_t> message, std::span<const uint8_t> mac) const {
  if (mac.size() != kMacBytes) return false;
  const Mac want = Compute(message);
  return crypto_verify_32(want.data(), mac.data()) == 0;
}

}  // namespace dt
