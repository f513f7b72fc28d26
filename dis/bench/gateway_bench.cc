// The DIS gateway's Entity State throughput against raw UDP on loopback, in one run
// (docs/performance.md, "DIS gateway"). BM_GatewayPair is the goal's measure: the raw baseline
// is a sendto and a recv of the same 144-byte datagram, both timed, and the gateway's side is
// the same pair with the gateway's work in it. Out: OnVehicleState (dead-reckoning check,
// geocentric conversion, encode, its sendto) and a raw recv of that datagram. In: a raw sendto
// of an outside Entity State, then the gateway's Receive and OnDatagram (decode, checks,
// conversion, in the "in_bus" variant also PduBus::Publish on memq://). Each iteration times a
// batch of raw pairs and a batch of gateway pairs, in alternating order; "ratio" is raw time ÷
// gateway time, the gateway's PDUs/s ÷ raw pairs/s. The one-sided benchmarks below it (the
// gateway's send or receive against a bare sendto or recv) are kept for comparison with earlier
// figures. BM_GatewayPairBundled is the same pair measure with the gateway's PDUs bundled. Manual
// time throughout: the thread's CPU time (a loopback sendto's delivery runs in
// the sender's thread), so other processes' turns on the shared machine do not count.
#include <benchmark/benchmark.h>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <ctime>
#include <memory>
#include <utility>
#include <vector>

#include "dis/dis_codec.h"
#include "dis/entity_translation.h"
#include "dis/gateway_core.h"
#include "dis/test/gateway_samples.h"
#include "dis/udp_endpoint.h"
#include "pdu/conversion.h"
#include "transport/pdu_bus.h"
#include "transport/transport.h"

namespace {

using namespace dt;
using namespace dt::dis;
// The thread's CPU time: on a shared machine wall time would also count other processes' turns.
struct Clock {
  static double now() {
    timespec t{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return static_cast<double>(t.tv_sec) + static_cast<double>(t.tv_nsec) * 1e-9;
  }
};

constexpr int kBatch = 64;  // well inside a default socket receive buffer
constexpr int kPort = 47301;
constexpr NodeAddress kNode{1, 1};

GatewaySettings Settings() { return SampleSettings(3, 1280.0, kNode); }

// The exercise bus the gateway publishes outside vehicles on, as the gateway's.
PduBusConfig BusConfig() {
  PduBusConfig bc;
  bc.exercise_id = 1;
  bc.local = Settings().self;
  bc.terrain_size_x_m = Settings().terrain_size_x_m;
  bc.terrain_size_z_m = Settings().terrain_size_z_m;
  return bc;
}

VehicleStateFields Tank(double x_m) {
  VehicleStateFields s = SampleTank({1, 1, 1}, x_m, 400.0, 0.3);
  s.velocity_mps = {3.0, 0.0, 1.0};
  return s;
}

std::vector<uint8_t> OutsideBytes(const GeodeticFrame& frame) {
  VehicleStateFields s = Tank(500.0);
  s.id = {31, 5, 777};
  EntityStatePdu pdu = EntityStateOfVehicle(s, frame, {3, 0}).value();
  return Encode(pdu);
}

std::unique_ptr<UdpEndpoint> Loopback() {
  // Sends to itself: the socket is its own receiver.
  return std::make_unique<UdpEndpoint>(UdpEndpointConfig{.bind_address = "127.0.0.1",
                                                         .port = kPort,
                                                         .destination = "127.0.0.1",
                                                         .interface_address = "127.0.0.1",
                                                         .multicast_ttl = 1});
}

int Drain(UdpEndpoint& e) {
  int n = 0;
  while (e.Receive()) ++n;
  return n;
}

// Which side of the gateway a pair benchmark runs.
enum class Side { kOut, kIn, kInBus };

// Per iteration one raw batch and one gateway batch, which goes first alternating so both see
// the same machine; the iteration's time is the gateway's. `after` runs after each iteration.
// Returns the raw and the gateway seconds, summed.
template <typename RawBatch, typename GatewayBatch, typename After>
std::pair<double, double> TimeAlternating(benchmark::State& state, RawBatch raw_batch,
                                          GatewayBatch gateway_batch, After after) {
  double raw_s = 0.0, gateway_s = 0.0;
  bool raw_first = true;
  for (auto _ : state) {
    double g = 0.0;
    if (raw_first) {
      raw_s += raw_batch();
      g = gateway_batch();
    } else {
      g = gateway_batch();
      raw_s += raw_batch();
    }
    raw_first = !raw_first;
    gateway_s += g;
    state.SetIterationTime(g);
    after();
  }
  return {raw_s, gateway_s};
}

void BM_GatewayPair(benchmark::State& state, Side side) {
  auto e = Loopback();
  auto memq = MakeTransport("memq://", 1);
  PduBus bus(*memq, BusConfig());
  uint64_t published = 0;
  GatewayCore core(
      Settings(), [&](std::span<const uint8_t> d) { return e->Send(d); },
      [&](const VehicleStateFields& s) -> Status {
        if (side == Side::kInBus) {
          if (auto r = bus.Publish(ToVehicleState(s)); !r) return r.error();
        } else {
          benchmark::DoNotOptimize(ToVehicleState(s));
        }
        ++published;
        return Status();
      });
  // Out, the raw pair sends what the gateway sends; in, what it receives. Both 144 bytes.
  const std::vector<uint8_t> bytes =
      side == Side::kOut ? Encode(EntityStateOfVehicle(Tank(100.0), core.frame(), {3, 0}).value())
                         : OutsideBytes(core.frame());
  const VehicleStateFields states[2] = {Tank(100.0), Tank(102.0)};  // 2 m apart: each one sent
  std::vector<uint8_t> buffer(kMaxPduSize + 1);
  sockaddr_in to{};
  to.sin_family = AF_INET;
  to.sin_port = htons(kPort);
  to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  auto raw_send = [&] {
    return ::sendto(e->fd(), bytes.data(), bytes.size(), 0, reinterpret_cast<const sockaddr*>(&to),
                    sizeof to) == static_cast<ssize_t>(bytes.size());
  };
  auto raw_recv = [&] { return ::recv(e->fd(), buffer.data(), buffer.size(), MSG_TRUNC) > 0; };
  double now_s = 0.0;
  int64_t raw_lost = 0, lost = 0;
  const uint64_t sent_before = core.counters().entity_state_sent;
  auto raw_batch = [&] {
    const auto t0 = Clock::now();
    for (int i = 0; i < kBatch; ++i) {
      if (!raw_send() || !raw_recv()) ++raw_lost;
    }
    return Clock::now() - t0;
  };
  auto gateway_batch = [&] {
    const auto t0 = Clock::now();
    for (int i = 0; i < kBatch; ++i) {
      if (side == Side::kOut) {
        now_s += 0.01;
        core.OnVehicleState(kNode, states[i & 1], now_s);
        if (!raw_recv()) ++lost;
      } else {
        if (!raw_send()) ++lost;
        const auto datagram = e->Receive();
        if (!datagram) {
          ++lost;
          continue;
        }
        core.OnDatagram(*datagram, 1.0);
      }
    }
    return Clock::now() - t0;
  };
  const auto [raw_s, gateway_s] = TimeAlternating(state, raw_batch, gateway_batch, [&] {
    if (side == Side::kInBus) (void)bus.HandleTimeout(0);
    while (e->Receive()) ++lost;  // nothing should be left over
  });
  const double pairs = static_cast<double>(state.iterations() * kBatch);
  state.SetItemsProcessed(state.iterations() * kBatch);
  state.counters["raw_pair_ns"] = raw_s / pairs * 1e9;
  state.counters["gateway_pair_ns"] = gateway_s / pairs * 1e9;
  state.counters["raw_pairs_per_s"] = pairs / raw_s;
  state.counters["ratio"] = raw_s / gateway_s;
  state.counters["raw_lost"] = static_cast<double>(raw_lost);
  const double done = side == Side::kOut
                          ? static_cast<double>(core.counters().entity_state_sent - sent_before)
                          : static_cast<double>(published);
  state.counters["lost"] = static_cast<double>(lost) + (pairs - done);
}
BENCHMARK_CAPTURE(BM_GatewayPair, out, Side::kOut)->UseManualTime();
BENCHMARK_CAPTURE(BM_GatewayPair, in, Side::kIn)->UseManualTime();
BENCHMARK_CAPTURE(BM_GatewayPair, in_bus, Side::kInBus)->UseManualTime();

// The same pair measure with bundling on (IEEE 1278.2, docs/dis.md "Bundling"): the raw baseline
// is unchanged (a sendto and a recv of one 144-byte PDU each), the gateway's side handles the
// same 64 PDUs bundled. Out: bundle_max_bytes 1400 (9 Entity States a datagram), 64
// OnVehicleState, a Flush, and a recv of each datagram. In: 8 raw sendto of a bundle of 8 outside
// Entity States (1152 bytes), each followed by the gateway's Receive and OnDatagram.
constexpr int kPerBundle = 8;
static_assert(kBatch % kPerBundle == 0);

void BM_GatewayPairBundled(benchmark::State& state, Side side) {
  auto e = Loopback();
  uint64_t published = 0;
  GatewaySettings settings = Settings();
  settings.bundle_max_bytes = 1400;
  GatewayCore core(
      settings, [&](std::span<const uint8_t> d) { return e->Send(d); },
      [&](const VehicleStateFields& s) -> Status {
        benchmark::DoNotOptimize(ToVehicleState(s));
        ++published;
        return Status();
      });
  const std::vector<uint8_t> bytes =
      side == Side::kOut ? Encode(EntityStateOfVehicle(Tank(100.0), core.frame(), {3, 0}).value())
                         : OutsideBytes(core.frame());
  std::vector<uint8_t> bundle;  // kPerBundle outside entities, one datagram
  for (int i = 0; i < kPerBundle; ++i) {
    VehicleStateFields s = Tank(500.0 + i);
    s.id = {31, 5, static_cast<uint16_t>(700 + i)};
    const std::vector<uint8_t> pdu = Encode(EntityStateOfVehicle(s, core.frame(), {3, 0}).value());
    bundle.insert(bundle.end(), pdu.begin(), pdu.end());
  }
  const VehicleStateFields states[2] = {Tank(100.0), Tank(102.0)};
  std::vector<uint8_t> buffer(kMaxPduSize + 1);
  sockaddr_in to{};
  to.sin_family = AF_INET;
  to.sin_port = htons(kPort);
  to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  auto send_raw = [&](const std::vector<uint8_t>& d) {
    return ::sendto(e->fd(), d.data(), d.size(), 0, reinterpret_cast<const sockaddr*>(&to),
                    sizeof to) == static_cast<ssize_t>(d.size());
  };
  auto raw_recv = [&] { return ::recv(e->fd(), buffer.data(), buffer.size(), MSG_TRUNC); };
  double now_s = 0.0;
  int64_t raw_lost = 0, received_pdus = 0, datagrams = 0;
  const uint64_t sent_before = core.counters().entity_state_sent;
  auto raw_batch = [&] {
    const auto t0 = Clock::now();
    for (int i = 0; i < kBatch; ++i) {
      if (!send_raw(bytes) || raw_recv() <= 0) ++raw_lost;
    }
    return Clock::now() - t0;
  };
  auto gateway_batch = [&] {
    const auto t0 = Clock::now();
    if (side == Side::kOut) {
      for (int i = 0; i < kBatch; ++i) {
        now_s += 0.01;
        core.OnVehicleState(kNode, states[i & 1], now_s);
      }
      core.Flush();
      for (ssize_t n; (n = ::recv(e->fd(), buffer.data(), buffer.size(), MSG_DONTWAIT)) > 0;) {
        received_pdus += n / static_cast<ssize_t>(kEntityStateSize);
        ++datagrams;
      }
    } else {
      for (int i = 0; i < kBatch / kPerBundle; ++i) {
        if (!send_raw(bundle)) continue;
        const auto datagram = e->Receive();
        if (!datagram) continue;
        ++datagrams;
        core.OnDatagram(*datagram, 1.0);
      }
    }
    return Clock::now() - t0;
  };
  const auto [raw_s, gateway_s] = TimeAlternating(state, raw_batch, gateway_batch, [&] {
    while (e->Receive()) ++raw_lost;  // nothing should be left over
  });
  const double pdus = static_cast<double>(state.iterations() * kBatch);
  state.SetItemsProcessed(state.iterations() * kBatch);
  state.counters["raw_pair_ns"] = raw_s / pdus * 1e9;
  state.counters["gateway_pdu_ns"] = gateway_s / pdus * 1e9;
  state.counters["ratio"] = raw_s / gateway_s;
  state.counters["pdus_per_datagram"] = pdus / static_cast<double>(datagrams);
  state.counters["raw_lost"] = static_cast<double>(raw_lost);
  const double done =
      side == Side::kOut
          ? static_cast<double>(std::min<uint64_t>(core.counters().entity_state_sent - sent_before,
                                                   static_cast<uint64_t>(received_pdus)))
          : static_cast<double>(published);
  state.counters["lost"] = pdus - done;
}
BENCHMARK_CAPTURE(BM_GatewayPairBundled, out, Side::kOut)->UseManualTime();
BENCHMARK_CAPTURE(BM_GatewayPairBundled, in, Side::kIn)->UseManualTime();

// The one-sided figures of earlier runs: the gateway's send or receive against a bare sendto or
// recv of the same bytes.
void BM_RawUdpOut(benchmark::State& state) {
  auto e = Loopback();
  GatewayCore core(Settings(), [](std::span<const uint8_t>) { return true; }, {});
  const std::vector<uint8_t> bytes =
      Encode(EntityStateOfVehicle(Tank(100.0), core.frame(), {3, 0}).value());
  sockaddr_in to{};
  to.sin_family = AF_INET;
  to.sin_port = htons(kPort);
  to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  int64_t lost = 0;
  for (auto _ : state) {
    const auto t0 = Clock::now();
    for (int i = 0; i < kBatch; ++i) {
      benchmark::DoNotOptimize(::sendto(e->fd(), bytes.data(), bytes.size(), 0,
                                        reinterpret_cast<const sockaddr*>(&to), sizeof to));
    }
    state.SetIterationTime(Clock::now() - t0);
    lost += kBatch - Drain(*e);
  }
  state.SetItemsProcessed(state.iterations() * kBatch);
  state.counters["lost"] = static_cast<double>(lost);
}
BENCHMARK(BM_RawUdpOut)->UseManualTime();

void BM_GatewayOut(benchmark::State& state) {
  auto e = Loopback();
  GatewayCore core(
      Settings(), [&](std::span<const uint8_t> d) { return e->Send(d); },
      [](const VehicleStateFields&) { return Status(); });
  // 2 m on each time: beyond the 1 m threshold, so every state is sent. Made before the timed
  // loop: the states are the node's, not the gateway's work.
  const VehicleStateFields states[2] = {Tank(100.0), Tank(102.0)};
  double now_s = 0.0;
  int64_t lost = 0;
  for (auto _ : state) {
    const auto t0 = Clock::now();
    for (int i = 0; i < kBatch; ++i) {
      now_s += 0.01;
      core.OnVehicleState(kNode, states[i & 1], now_s);
    }
    state.SetIterationTime(Clock::now() - t0);
    lost += kBatch - Drain(*e);
  }
  state.SetItemsProcessed(state.iterations() * kBatch);
  state.counters["lost"] = static_cast<double>(lost);
  state.counters["sent"] = static_cast<double>(core.counters().entity_state_sent);
}
BENCHMARK(BM_GatewayOut)->UseManualTime();

void Fill(UdpEndpoint& e, const std::vector<uint8_t>& bytes) {
  for (int i = 0; i < kBatch; ++i) (void)e.Send(bytes);
}

void BM_RawUdpIn(benchmark::State& state) {
  auto e = Loopback();
  const std::vector<uint8_t> bytes = OutsideBytes(GeodeticFrame(Settings().origin));
  std::vector<uint8_t> buffer(kMaxPduSize + 1);
  int64_t received = 0;
  for (auto _ : state) {
    Fill(*e, bytes);
    const auto t0 = Clock::now();
    for (int i = 0; i < kBatch; ++i) {
      if (::recv(e->fd(), buffer.data(), buffer.size(), MSG_TRUNC) > 0) ++received;
    }
    state.SetIterationTime(Clock::now() - t0);
  }
  state.SetItemsProcessed(state.iterations() * kBatch);
  state.counters["lost"] = static_cast<double>(state.iterations() * kBatch - received);
}
BENCHMARK(BM_RawUdpIn)->UseManualTime();

// to_bus: published on a PduBus over memq:// (drained untimed), else only converted.
void BM_GatewayIn(benchmark::State& state, bool to_bus) {
  auto e = Loopback();
  auto memq = MakeTransport("memq://", 1);
  PduBus bus(*memq, BusConfig());
  uint64_t published = 0;
  GatewayCore core(
      Settings(), [](std::span<const uint8_t>) { return true; },
      [&](const VehicleStateFields& s) -> Status {
        if (to_bus) {
          if (auto r = bus.Publish(ToVehicleState(s)); !r) return r.error();
        } else {
          benchmark::DoNotOptimize(ToVehicleState(s));
        }
        ++published;
        return Status();
      });
  const std::vector<uint8_t> bytes = OutsideBytes(core.frame());
  for (auto _ : state) {
    Fill(*e, bytes);
    const auto t0 = Clock::now();
    for (int i = 0; i < kBatch; ++i) {
      const auto datagram = e->Receive();
      if (!datagram) break;
      core.OnDatagram(*datagram, 1.0);
    }
    state.SetIterationTime(Clock::now() - t0);
    if (to_bus) (void)bus.HandleTimeout(0);
  }
  state.SetItemsProcessed(state.iterations() * kBatch);
  state.counters["lost"] = static_cast<double>(state.iterations() * kBatch - published);
}
BENCHMARK_CAPTURE(BM_GatewayIn, converted, false)->UseManualTime();
BENCHMARK_CAPTURE(BM_GatewayIn, bus, true)->UseManualTime();

// Latency of the gateway's path, from a node's state change to the DIS datagram on the wire: a
// node's PduBus publishes a VehicleState 2 m on (memq://, one thread), the gateway's bus
// dispatches it to GatewayCore, which sends the Entity State, and the datagram is received from
// the socket; thread CPU time per state (the wake-ups of separate processes are not in it).
// "raw" is the same path without the gateway's work: the VehicleState through both buses as
// above, then sendto + recv of the Entity State's bytes encoded beforehand; the difference is
// what the gateway adds.
void BM_StateToDatagram(benchmark::State& state, bool gateway) {
  auto e = Loopback();
  auto memq = MakeTransport("memq://", 1);
  PduBusConfig nc;
  nc.exercise_id = 1;
  nc.local = kNode;
  nc.terrain_size_x_m = Settings().terrain_size_x_m;
  nc.terrain_size_z_m = Settings().terrain_size_z_m;
  PduBusConfig gc = nc;
  gc.local = Settings().self;
  PduBus node(*memq, nc);
  PduBus bus(*memq, gc);
  GatewayCore core(
      Settings(), [&](std::span<const uint8_t> d) { return e->Send(d); },
      [](const VehicleStateFields&) { return Status(); });
  const std::vector<uint8_t> es =
      Encode(EntityStateOfVehicle(Tank(100.0), core.frame(), {3, 0}).value());
  double now_s = 0.0;
  int64_t heard = 0;
  bus.Subscribe<dtpdu::vehicle_state_t>([&](const dtpdu::vehicle_state_t& pdu) {
    ++heard;
    if (gateway) core.OnVehicleState(kNode, FromVehicleState(pdu), now_s);
  });
  int64_t received = 0, i = 0;
  for (auto _ : state) {
    now_s += 0.01;
    const auto t0 = Clock::now();
    (void)node.Publish(ToVehicleState(Tank((++i & 1) ? 102.0 : 100.0)));
    (void)bus.HandleTimeout(0);
    if (!gateway) (void)e->Send(es);
    if (e->Receive()) ++received;
    state.SetIterationTime(Clock::now() - t0);
  }
  state.counters["heard"] = static_cast<double>(heard);
  state.counters["lost"] = static_cast<double>(state.iterations() - received);
}
BENCHMARK_CAPTURE(BM_StateToDatagram, raw, false)->UseManualTime();
BENCHMARK_CAPTURE(BM_StateToDatagram, gateway, true)->UseManualTime();

}  // namespace

BENCHMARK_MAIN();
