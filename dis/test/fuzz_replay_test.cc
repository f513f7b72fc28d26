// Replays the DIS fuzz seed corpus and random corruptions through the fuzz body in every build:
// no input crashes, and only the corpus's valid inputs are accepted.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <random>

#include "dis/dis_codec.h"
#include "dis/fuzz/decode_one.h"
#include "dis/test/golden_pdus.h"

namespace dt::dis {
namespace {

bool Accepted(const std::vector<uint8_t>& input) {
  return fuzz::DecodeOne(input.data(), input.size());
}

TEST(DisFuzzReplay, TheSeedCorpusRunsAndOnlyItsValidInputsAreAccepted) {
  size_t files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(DT_DIS_CORPUS_DIR)) {
    std::ifstream in(entry.path(), std::ios::binary);
    const std::vector<uint8_t> bytes{std::istreambuf_iterator<char>(in), {}};
    const std::string name = entry.path().filename().string();
    const bool valid = name.find("_valid") != std::string::npos;
    EXPECT_EQ(Accepted(bytes), valid) << name;
    ++files;
  }
  EXPECT_GE(files, 40u);
}

// The corpus's bundles reach the fuzz body whole; read as the gateway reads them, each keeps its
// good PDUs and refuses only the bad one or the tail that cannot be framed.
TEST(DisFuzzReplay, TheCorpusBundlesSplitIntoTheirPdus) {
  const std::map<std::string, std::pair<int, int>> expected = {
      {"bundle_entity_point_linear", {3, 0}},
      {"bundle_bad_between_good", {2, 1}},
      {"bundle_truncated_tail", {1, 1}},
      {"bundle_length_below_header", {1, 1}}};
  for (const auto& [name, counts] : expected) {
    std::ifstream in(std::filesystem::path(DT_DIS_CORPUS_DIR) / name, std::ios::binary);
    const std::vector<uint8_t> bytes{std::istreambuf_iterator<char>(in), {}};
    ASSERT_FALSE(bytes.empty()) << name;
    EXPECT_FALSE(Accepted(bytes)) << name;  // no bundle is one whole PDU
    Decoder decoder(fuzz::kFuzzExercise);
    int accepted = 0, refused = 0;
    decoder.DecodeBundle(bytes, [&](const DecodeResult& r) { ++(r.ok() ? accepted : refused); });
    EXPECT_EQ(accepted, counts.first) << name;
    EXPECT_EQ(refused, counts.second) << name;
  }
}

TEST(DisFuzzReplay, RandomCorruptionsNeverCrash) {
  std::mt19937_64 rng(2026);
  std::vector<std::vector<uint8_t>> inputs;
  for (auto pdu : {Encode(testing::GoldenEntityState()), Encode(testing::GoldenPointObjectState()),
                   Encode(testing::GoldenLinearObjectState())}) {
    pdu[1] = fuzz::kFuzzExercise;
    inputs.push_back(pdu);
  }
  for (const auto& base : inputs) {
    ASSERT_TRUE(Accepted(base));
    for (int i = 0; i < 3000; ++i) {
      std::vector<uint8_t> b = base;
      const int flips = 1 + static_cast<int>(rng() % 4);
      for (int f = 0; f < flips; ++f) {
        // Spare the header's first 12 bytes half the time so the body's checks are reached.
        const size_t from = (rng() & 1) ? kHeaderSize : 0;
        b[from + rng() % (b.size() - from)] = static_cast<uint8_t>(rng());
      }
      (void)Accepted(b);
    }
  }
}

}  // namespace
}  // namespace dt::dis
