// Tests SimNetwork: delivery, virtual time, faults, partitions, exercises and determinism.
#include "simulation/sim_network.h"

#include <poll.h>

#include <map>
#include <set>
#include <stdexcept>

#include <gtest/gtest.h>

#include "pdu/pdu_traits.h"
#include "pdu/test/sample_pdus.h"

namespace dt {
namespace {

// A message: sender_seq carries a message number so receivers can log what arrived.
std::vector<uint8_t> Message(NodeAddress from, int64_t number) {
  auto pdu = sample::MaxFeature();
  pdu.sender = ToPdu(from);
  pdu.sender_seq = number;
  return EncodePdu(pdu);
}

struct Received {
  NodeAddress from;
  int64_t number;
  auto operator<=>(const Received&) const = default;
};

struct Node {
  NodeAddress address;
  std::unique_ptr<Transport> transport;
  std::vector<Received> log;
};

std::vector<std::unique_ptr<Node>> MakeNodes(SimNetwork& net, int n, uint8_t exercise = 1) {
  std::vector<std::unique_ptr<Node>> nodes;
  for (int i = 0; i < n; ++i) {
    auto node = std::make_unique<Node>();
    node->address = {1, static_cast<uint16_t>(i + 1)};
    node->transport = net.Join(node->address, exercise);
    Node* raw = node.get();
    node->transport->Subscribe(PduType::kMaxFeature, [raw](std::span<const uint8_t> b) {
      dtpdu::max_feature_t pdu;
      if (!DecodePdu(b, pdu)) raw->log.push_back({FromPdu(pdu.sender), pdu.sender_seq});
    });
    nodes.push_back(std::move(node));
  }
  return nodes;
}

void HandleAll(std::vector<std::unique_ptr<Node>>& nodes) {
  for (auto& n : nodes) ASSERT_TRUE(n->transport->HandleTimeout(0).ok());
}

// Runs a fixed scenario and returns every node's receive log.
std::vector<std::vector<Received>> RunScenario(uint64_t seed, FaultConfig faults) {
  SimNetwork net(seed, faults);
  auto nodes = MakeNodes(net, 4);
  for (int step = 0; step < 200; ++step) {
    for (auto& n : nodes) {
      EXPECT_TRUE(n->transport->Publish(PduType::kMaxFeature, Message(n->address, step + 1)).ok());
    }
    net.AdvanceMs(1);
    HandleAll(nodes);
  }
  net.AdvanceMs(1000);
  HandleAll(nodes);
  std::vector<std::vector<Received>> logs;
  for (auto& n : nodes) logs.push_back(n->log);
  return logs;
}

TEST(SimNetwork, WithoutFaultsEveryNodeGetsEveryMessageOnceInOrder) {
  SimNetwork net(1);
  auto nodes = MakeNodes(net, 3);
  for (int k = 1; k <= 5; ++k) {
    for (auto& n : nodes) {
      ASSERT_TRUE(n->transport->Publish(PduType::kMaxFeature, Message(n->address, k)).ok());
    }
  }
  HandleAll(nodes);
  for (auto& n : nodes) {
    ASSERT_EQ(n->log.size(), 15u);
    for (size_t i = 0; i < 15; ++i) {
      EXPECT_EQ(n->log[i].number, static_cast<int64_t>(i / 3 + 1));
      EXPECT_EQ(n->log[i].from, nodes[i % 3]->address);
    }
  }
  EXPECT_EQ(net.in_flight(), 0u);
  EXPECT_EQ(net.stats().delivered, 45u);
}

TEST(SimNetwork, SameSeedSameOutcomeDifferentSeedDifferentOutcome) {
  FaultConfig f;
  f.drop_probability = 0.2;
  f.duplicate_probability = 0.1;
  f.min_delay = 0;
  f.max_delay = 5;
  f.reorder_probability = 0.2;
  f.reorder_window = 20;
  const auto a = RunScenario(42, f);
  const auto b = RunScenario(42, f);
  const auto c = RunScenario(43, f);
  EXPECT_EQ(a, b);
  EXPECT_NE(a, c);
}

TEST(SimNetwork, DropsAboutTheConfiguredFraction) {
  FaultConfig f;
  f.drop_probability = 0.3;
  const auto logs = RunScenario(7, f);
  // Each node gets its own 200 messages unfaulted plus about 70% of the other three's 600.
  for (const auto& log : logs) {
    const double others = static_cast<double>(log.size()) - 200.0;
    EXPECT_GT(others, 600 * 0.7 - 60);
    EXPECT_LT(others, 600 * 0.7 + 60);
  }
}

TEST(SimNetwork, DuplicatesWhenAsked) {
  FaultConfig f;
  f.duplicate_probability = 1.0;
  const auto logs = RunScenario(7, f);
  for (const auto& log : logs) EXPECT_EQ(log.size(), 200u + 2 * 600u);
}

TEST(SimNetwork, DelaysInVirtualTimeAndSignalsTheFd) {
  FaultConfig f;
  f.min_delay = 50;
  f.max_delay = 50;
  SimNetwork net(3, f);
  auto nodes = MakeNodes(net, 2);
  ASSERT_TRUE(nodes[0]->transport->Publish(PduType::kMaxFeature, Message({1, 1}, 1)).ok());
  pollfd p{nodes[1]->transport->Fd(), POLLIN, 0};
  EXPECT_EQ(poll(&p, 1, 0), 0);
  net.AdvanceMs(49);
  HandleAll(nodes);
  EXPECT_TRUE(nodes[1]->log.empty());
  EXPECT_EQ(nodes[0]->log.size(), 1u);  // loopback is never delayed
  EXPECT_EQ(net.NextDeliveryMs(), 50);
  net.AdvanceMs(1);
  EXPECT_EQ(poll(&p, 1, 0), 1);
  HandleAll(nodes);
  EXPECT_EQ(nodes[1]->log.size(), 1u);
  EXPECT_EQ(poll(&p, 1, 0), 0);
  EXPECT_EQ(net.NextDeliveryMs(), -1);
}

TEST(SimNetwork, ReordersWhenAsked) {
  FaultConfig f;
  f.reorder_probability = 0.5;
  f.reorder_window = 10;
  const auto logs = RunScenario(11, f);
  const auto& log = logs[1];
  ASSERT_EQ(log.size(), 800u);  // nothing lost
  bool out_of_order = false;
  std::map<NodeAddress, int64_t> last;
  for (const auto& r : log) {
    if (r.number < last[r.from]) out_of_order = true;
    last[r.from] = std::max(last[r.from], r.number);
  }
  EXPECT_TRUE(out_of_order);
}

TEST(SimNetwork, PartitionsCutTrafficBothWaysUntilHealed) {
  SimNetwork net(5);
  auto nodes = MakeNodes(net, 3);
  net.faults().Partition({nodes[0]->address}, {nodes[1]->address});
  for (auto& n : nodes) {
    ASSERT_TRUE(n->transport->Publish(PduType::kMaxFeature, Message(n->address, 1)).ok());
  }
  HandleAll(nodes);
  auto from = [](const Node& n) {
    std::set<NodeAddress> s;
    for (const auto& r : n.log) s.insert(r.from);
    return s;
  };
  EXPECT_EQ(from(*nodes[0]), (std::set<NodeAddress>{nodes[0]->address, nodes[2]->address}));
  EXPECT_EQ(from(*nodes[1]), (std::set<NodeAddress>{nodes[1]->address, nodes[2]->address}));
  EXPECT_EQ(nodes[2]->log.size(), 3u);
  net.faults().Heal();
  net.faults().Isolate(nodes[2]->address);
  ASSERT_TRUE(nodes[0]->transport->Publish(PduType::kMaxFeature, Message({1, 1}, 2)).ok());
  HandleAll(nodes);
  EXPECT_EQ(nodes[1]->log.back(), (Received{{1, 1}, 2}));
  EXPECT_EQ(nodes[2]->log.size(), 3u);
}

TEST(SimNetwork, ExercisesNeverSeeEachOther) {
  SimNetwork net(5);
  auto one = MakeNodes(net, 1, 1);
  auto two = MakeNodes(net, 1, 2);  // same node address, other exercise
  ASSERT_TRUE(one[0]->transport->Publish(PduType::kMaxFeature, Message({1, 1}, 1)).ok());
  HandleAll(one);
  HandleAll(two);
  EXPECT_EQ(one[0]->log.size(), 1u);
  EXPECT_TRUE(two[0]->log.empty());
  EXPECT_THROW(net.Join({1, 1}, 1), std::invalid_argument);
}

TEST(SimNetwork, AReplyPublishedByAHandlerWaitsForTheNextCall) {
  SimNetwork net(5);
  auto a = net.Join({1, 1}, 1);
  int got = 0;
  a->Subscribe(PduType::kPlayback, [&](std::span<const uint8_t> b) {
    ++got;
    EXPECT_TRUE(a->Publish(PduType::kPlayback, b).ok());
  });
  ASSERT_TRUE(a->Publish(PduType::kPlayback, EncodePdu(sample::Playback())).ok());
  EXPECT_EQ(a->HandleTimeout(0).value(), 1);
  EXPECT_EQ(got, 1);
  EXPECT_EQ(a->HandleTimeout(0).value(), 1);
  EXPECT_EQ(got, 2);
  EXPECT_FALSE(a->Publish(PduType::kPlayback, std::vector<uint8_t>(kMaxPduBytes + 1)).ok());
}

TEST(SimNetwork, BlockedWritesFailUntilTheirWindowEndsAndReceivingGoesOn) {
  SimNetwork net(6);
  auto nodes = MakeNodes(net, 2);
  Node& a = *nodes[0];
  Node& b = *nodes[1];
  net.BlockWrites(a.address, 100);
  EXPECT_TRUE(net.WritesBlocked(a.address));
  EXPECT_FALSE(net.WritesBlocked(b.address));
  const Status failed = a.transport->Publish(PduType::kMaxFeature, Message(a.address, 1));
  ASSERT_FALSE(failed.ok());
  EXPECT_NE(failed.error().message.find("timed out"), std::string::npos) << failed.error().message;
  // The blocked node still receives.
  ASSERT_TRUE(b.transport->Publish(PduType::kMaxFeature, Message(b.address, 2)).ok());
  HandleAll(nodes);
  EXPECT_EQ(a.log, (std::vector<Received>{{b.address, 2}}));
  EXPECT_EQ(b.log, (std::vector<Received>{{b.address, 2}}));  // nothing of a's
  EXPECT_EQ(net.stats().write_failures, 1u);
  EXPECT_EQ(net.stats().published, 1u);

  net.AdvanceMs(99);
  EXPECT_FALSE(a.transport->Publish(PduType::kMaxFeature, Message(a.address, 3)).ok());
  net.AdvanceMs(1);  // the window ends at 100 ms
  EXPECT_FALSE(net.WritesBlocked(a.address));
  ASSERT_TRUE(a.transport->Publish(PduType::kMaxFeature, Message(a.address, 4)).ok());
  HandleAll(nodes);
  EXPECT_EQ(b.log, (std::vector<Received>{{b.address, 2}, {a.address, 4}}));
  EXPECT_EQ(net.stats().write_failures, 2u);
}

TEST(SimNetwork, ALaterBlockWritesReplacesTheWindowAndZeroEndsIt) {
  SimNetwork net(7);
  auto a = net.Join({1, 1}, 1);
  const auto bytes = EncodePdu(sample::MaxFeature());
  net.BlockWrites({1, 1}, 50);
  net.BlockWrites({1, 1}, 500);  // replaces, does not add to, the first window
  net.AdvanceMs(60);
  EXPECT_FALSE(a->Publish(PduType::kMaxFeature, bytes).ok());
  net.BlockWrites({1, 1}, 0);
  EXPECT_TRUE(a->Publish(PduType::kMaxFeature, bytes).ok());
}

TEST(FaultModel, RefusesBadConfigs) {
  FaultConfig f;
  f.drop_probability = 1.5;
  EXPECT_THROW(FaultModel(f, 1), std::invalid_argument);
  f = {};
  f.min_delay = 5;
  f.max_delay = 4;
  EXPECT_THROW(FaultModel(f, 1), std::invalid_argument);
}

}  // namespace
}  // namespace dt
