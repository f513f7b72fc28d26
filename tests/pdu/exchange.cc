#include "tests/pdu/exchange.h"

#include <fmt/format.h>

#include <vector>

#include "pdu/conversion.h"
#include "transport/dds_transport.h"
#include "transport/pdu_bus.h"

namespace dt::exchange {

std::string Result::ToLine() const {
  return fmt::format("sent={} received={} duplicates={} rejected={} finished={}", sent, received,
                     duplicates, rejected, finished ? 1 : 0);
}

bool AwaitPeerReaders(Transport& transport, int timeout_ms) {
  auto* dds = dynamic_cast<DdsTransport*>(&transport);
  if (dds == nullptr) return true;
  // Our own reader plus the peer's.
  return dds->WaitForReaders(PduType::kUpdate, 2, timeout_ms) &&
         dds->WaitForReaders(PduType::kMaxFeature, 2, timeout_ms);
}

Result Run(Transport& transport, NodeAddress local, int64_t count,
           std::chrono::steady_clock::time_point deadline, const std::function<void()>& ready,
           int64_t window) {
  PduBusConfig config;
  config.exercise_id = kExercise;
  config.local = local;
  config.terrain_size_x_m = config.terrain_size_z_m = kTerrainM;
  PduBus bus(transport, config);

  Result result;
  std::vector<bool> seen(static_cast<size_t>(count) + 1, false);
  int64_t peer_acked = 0;
  bus.Subscribe<dtpdu::update_t>([&](const dtpdu::update_t& pdu) {
    const int64_t n = pdu.change_seq;
    if (n < 1 || n > count) return;
    if (seen[static_cast<size_t>(n)]) {
      ++result.duplicates;
    } else {
      seen[static_cast<size_t>(n)] = true;
      ++result.received;
    }
  });
  bus.Subscribe<dtpdu::max_feature_t>([&](const dtpdu::max_feature_t& pdu) {
    peer_acked = std::max(peer_acked, pdu.max_change_seq);
  });
  ready();

  FeaturePdu feature;
  feature.params = FeatureParams::Crater(500.0, 500.0, 3.0);
  int64_t last_ack = -1;
  while (std::chrono::steady_clock::now() < deadline) {
    if (result.sent == count && result.received == count) {
      result.finished = true;
      break;
    }
    int batch = 0;
    while (result.sent < count && result.sent - peer_acked < window && batch < 100) {
      feature.id = {local.site, local.host, static_cast<uint32_t>(result.sent + 1)};
      feature.change = {local, static_cast<uint32_t>(result.sent + 1),
                        static_cast<uint64_t>(result.sent + 1)};
      if (!bus.Publish(ToUpdate(feature)).ok()) break;
      ++result.sent;
      ++batch;
    }
    auto handled = bus.HandleTimeout(batch > 0 ? 0 : 20);
    if (!handled.ok()) break;
    // Acknowledge progress in steps, and again whenever idle in case an acknowledgement was lost.
    if (result.received - last_ack >= 100 || (handled.value() == 0 && batch == 0)) {
      dtpdu::max_feature_t ack{};
      ack.max_change_seq = result.received;
      ack.max_feature_number = result.sent;
      ack.lamport = result.received;
      if (bus.Publish(ack).ok()) last_ack = result.received;
    }
  }
  // A final acknowledgement lets the peer's window drain if it still waits for one.
  dtpdu::max_feature_t ack{};
  ack.max_change_seq = result.received;
  ack.max_feature_number = result.sent;
  (void)bus.Publish(ack);
  result.rejected = bus.rejects().total();
  return result;
}

}  // namespace dt::exchange
