// Replays the fuzz seed corpus and systematic corruptions through decode + validate, so every
// build (and asan-ubsan) covers what the fuzzer covers: no input crashes, and damaged PDUs are
// rejected.
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>

#include <gtest/gtest.h>

#include "pdu/fuzz/decode_validate.h"
#include "pdu/test/sample_pdus.h"

namespace dt {
namespace {

std::vector<uint8_t> WithSelector(uint8_t selector, std::vector<uint8_t> bytes) {
  bytes.insert(bytes.begin(), selector);
  return bytes;
}

bool Accepted(const std::vector<uint8_t>& input) {
  return fuzz::DecodeValidateOne(input.data(), input.size());
}

TEST(FuzzReplay, TheSeedCorpusRunsAndOnlyItsValidInputsAreAccepted) {
  size_t files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(DT_PDU_CORPUS_DIR)) {
    std::ifstream in(entry.path(), std::ios::binary);
    const std::vector<uint8_t> bytes{std::istreambuf_iterator<char>(in), {}};
    const std::string name = entry.path().filename().string();
    const bool valid = name.find("_valid") != std::string::npos || name == "construct_all_edits";
    EXPECT_EQ(Accepted(bytes), valid) << name;
    ++files;
  }
  EXPECT_GE(files, 60u);
}

TEST(FuzzReplay, EveryTruncationIsRejected) {
  const std::vector<std::vector<uint8_t>> inputs = {
      WithSelector(0, EncodePdu(sample::Construct())),
      WithSelector(1, EncodePdu(sample::Update())),
      WithSelector(2, EncodePdu(sample::Destruct())),
      WithSelector(3, EncodePdu(sample::MaxFeature())),
      WithSelector(4, EncodePdu(sample::Playback())),
      WithSelector(5, EncodePdu(sample::AntiEntropySummary())),
      WithSelector(5, EncodePdu(sample::AntiEntropyHashes())),
      WithSelector(5, EncodePdu(sample::AntiEntropyCopies())),
      WithSelector(6, EncodePdu(sample::VehicleState()))};
  for (const auto& full : inputs) {
    ASSERT_TRUE(Accepted(full));
    for (size_t n = 0; n < full.size(); ++n) {
      EXPECT_FALSE(Accepted({full.begin(), full.begin() + static_cast<long>(n)})) << n;
    }
  }
}

TEST(FuzzReplay, RandomCorruptionsNeverCrash) {
  std::mt19937_64 rng(2024);
  const std::vector<std::vector<uint8_t>> inputs = {
      WithSelector(0, EncodePdu(sample::Construct())),
      WithSelector(1, EncodePdu(sample::Update())),
      WithSelector(2, EncodePdu(sample::Destruct())),
      WithSelector(3, EncodePdu(sample::MaxFeature())),
      WithSelector(4, EncodePdu(sample::Playback())),
      WithSelector(5, EncodePdu(sample::AntiEntropySummary())),
      WithSelector(5, EncodePdu(sample::AntiEntropyHashes())),
      WithSelector(5, EncodePdu(sample::AntiEntropyCopies())),
      WithSelector(6, EncodePdu(sample::VehicleState()))};
  size_t accepted = 0;
  size_t total = 0;
  for (const auto& full : inputs) {
    for (int i = 0; i < 4000; ++i) {
      auto bytes = full;
      const int edits = 1 + static_cast<int>(rng() % 4);
      for (int e = 0; e < edits; ++e) {
        bytes[1 + rng() % (bytes.size() - 1)] = static_cast<uint8_t>(rng());
      }
      accepted += Accepted(bytes) ? 1 : 0;
      ++total;
    }
  }
  // Some corruptions land in fields any value of which is valid (time stamps, counters); most
  // break the fingerprint or a checked field.
  EXPECT_GT(accepted, 0u);
  EXPECT_LT(accepted, total / 2);
}

}  // namespace
}  // namespace dt
