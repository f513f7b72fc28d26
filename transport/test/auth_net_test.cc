// Authentication is above the Transport, so it holds on every carrier: over memq, udpm and DDS
// every PDU type arrives authenticated, and a PDU without a trailer, one signed with another key
// and a captured PDU sent again are dropped and counted. Runs in a private network namespace.
#include <chrono>
#include <functional>

#include <gtest/gtest.h>

#include "pdu/test/sample_pdus.h"
#include "transport/dds_transport.h"
#include "transport/pdu_bus.h"
#include "transport/test/handle_until.h"
#include "transport/test/private_netns.h"

namespace dt {
namespace {

constexpr const char* kUdpm = "udpm://239.255.76.67:7667?ttl=0";
const std::string kDds =
    std::string("dds://0?config=") + DT_SOURCE_DIR + "/configs/cyclonedds-loopback.xml";

std::shared_ptr<const ExerciseKey> Key(uint8_t fill) {
  return std::make_shared<const ExerciseKey>(std::vector<uint8_t>(32, fill));
}

PduBusConfig Config(NodeAddress local, std::shared_ptr<const ExerciseKey> key) {
  PduBusConfig c;
  c.exercise_id = sample::kSampleExercise;
  c.local = local;
  c.terrain_size_x_m = c.terrain_size_z_m = sample::kSampleTerrainM;
  c.auth.key = std::move(key);
  return c;
}

using testing::HandleUntil;

// The types the test sends (and its receiver subscribes to).
constexpr PduType kSentTypes[] = {PduType::kConstruct,  PduType::kUpdate,   PduType::kDestruct,
                                  PduType::kMaxFeature, PduType::kPlayback, PduType::kVehicleState};

void AwaitReaders(Transport& sender, int readers) {
  if (auto* dds = dynamic_cast<DdsTransport*>(&sender)) {
    for (PduType type : kSentTypes) {
      ASSERT_TRUE(dds->WaitForReaders(type, readers, 10000)) << PduTypeName(type);
    }
  }
}

class AuthOnEveryCarrier : public ::testing::TestWithParam<std::string> {};

TEST_P(AuthOnEveryCarrier, AuthenticPdusArriveAndForgeriesAndReplaysDoNot) {
  if (auto reason = testing::NetnsSkipReason()) GTEST_SKIP() << *reason;
  const std::string url = GetParam();
  auto a = MakeTransport(url, sample::kSampleExercise);
  std::unique_ptr<Transport> b_owned;
  Transport* b = a.get();
  if (url != "memq://") {
    b_owned = MakeTransport(url, sample::kSampleExercise);
    b = b_owned.get();
  }
  const auto key = Key(0x5A);
  PduBus from(*a, Config({1, 2}, key));
  PduBus to(*b, Config({2, 2}, key));
  int got = 0;
  std::vector<std::vector<uint8_t>> raw;  // what `to` receives, as carried
  to.Subscribe<dtpdu::construct_t>([&](const dtpdu::construct_t&) { ++got; });
  to.Subscribe<dtpdu::update_t>([&](const dtpdu::update_t&) { ++got; });
  to.Subscribe<dtpdu::destruct_t>([&](const dtpdu::destruct_t&) { ++got; });
  to.Subscribe<dtpdu::max_feature_t>([&](const dtpdu::max_feature_t&) { ++got; });
  to.Subscribe<dtpdu::playback_t>([&](const dtpdu::playback_t&) { ++got; });
  to.Subscribe<dtpdu::vehicle_state_t>([&](const dtpdu::vehicle_state_t&) { ++got; });
  b->Subscribe(PduType::kConstruct, [&](std::span<const uint8_t> bytes) {
    raw.emplace_back(bytes.begin(), bytes.end());
  });
  // Only `to` reads (one reader per type on b).
  AwaitReaders(*a, 1);

  ASSERT_TRUE(from.Publish(sample::Construct()).ok());
  ASSERT_TRUE(from.Publish(sample::Update()).ok());
  ASSERT_TRUE(from.Publish(sample::Destruct()).ok());
  ASSERT_TRUE(from.Publish(sample::MaxFeature()).ok());
  ASSERT_TRUE(from.Publish(sample::Playback()).ok());
  ASSERT_TRUE(from.Publish(sample::VehicleState()).ok());
  ASSERT_TRUE(HandleUntil({a.get(), b}, [&] { return got == 6; })) << got << " of 6 arrived";
  EXPECT_EQ(to.rejects().total(), 0u);
  ASSERT_EQ(raw.size(), 1u);
  // The carrier kept the trailer byte for byte: the LCM PDU is followed by exactly 64 bytes.
  EXPECT_EQ(raw[0].size(), EncodePdu(sample::Construct()).size() + kAuthTrailerBytes);

  // The captured Construct again, the same PDU without a trailer, and signed with another key.
  PduAuthenticator stranger({1, 2}, PduAuthConfig{.key = Key(0x77)});
  std::vector<uint8_t> other_key = EncodePdu(sample::Construct());
  stranger.Sign(other_key);
  ASSERT_TRUE(a->Publish(PduType::kConstruct, raw[0]).ok());
  ASSERT_TRUE(a->Publish(PduType::kConstruct, EncodePdu(sample::Construct())).ok());
  ASSERT_TRUE(a->Publish(PduType::kConstruct, other_key).ok());
  ASSERT_TRUE(HandleUntil({a.get(), b}, [&] { return to.rejects().total() == 3; }))
      << to.rejects().total() << " of 3 rejected";
  EXPECT_EQ(to.rejects().count(RejectReason::kReplayed), 1u);
  EXPECT_EQ(to.rejects().count(RejectReason::kUnauthenticated), 1u);
  EXPECT_EQ(to.rejects().count(RejectReason::kBadMac), 1u);
  EXPECT_EQ(got, 6);
}

INSTANTIATE_TEST_SUITE_P(Carriers, AuthOnEveryCarrier, ::testing::Values("memq://", kUdpm, kDds),
                         [](const auto& param_info) {
                           return param_info.param.substr(0, param_info.param.find(':'));
                         });

}  // namespace
}  // namespace dt

int main(int argc, char** argv) {
  dt::testing::EnterPrivateNetns(argc, argv);
  if (auto reason = dt::testing::NetnsSkipReason()) {
    std::fprintf(stderr, "network tests skipped: %s\n", reason->c_str());
  }
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
