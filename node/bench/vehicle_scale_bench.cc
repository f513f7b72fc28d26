// Shared vehicles at scale (docs/performance.md "Shared vehicles at scale"): three nodes of N
// wandering vehicles each (default 10 000, light unless --model physical) on one terrain; node 1
// owns its N and receives the other 2N. Per 30 Hz tick it times node 1's own vehicles (wander,
// advance, dead-reckoning bookkeeping and sending) and its receiver path (decode and validate the
// VehicleState PDUs the other two sent in that tick, apply them, then dead reckon and settle every
// remote vehicle on its terrain), in CPU time against the 33.3 ms budget of one core; and it counts
// the PDUs the 2N cost.
//
//   vehicle_scale_bench [--vehicles N] [--seconds S] [--craters C] [--model light|physical]
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <optional>
#include <string>
#include <vector>

#include "log/log.h"
#include "node/bench/vehicle_fleet.h"

namespace dt::bench {
namespace {

struct Stats {
  double mean = 0, p50 = 0, p99 = 0, max = 0;
};

Stats Summarise(std::vector<double> v) {
  Stats s;
  if (v.empty()) return s;
  std::sort(v.begin(), v.end());
  for (double x : v) s.mean += x;
  s.mean /= static_cast<double>(v.size());
  s.p50 = v[v.size() / 2];
  s.p99 = v[std::min(v.size() - 1, v.size() * 99 / 100)];
  s.max = v.back();
  return s;
}

void Print(const char* what, const Stats& s) {
  std::printf(
      "  %-44s mean %7.2f  p50 %7.2f  p99 %7.2f  max %7.2f ms  (%.0f %% of 33.3 ms at p99)\n", what,
      s.mean * 1e3, s.p50 * 1e3, s.p99 * 1e3, s.max * 1e3, s.p99 * 1e3 / 33.333 * 100);
}

int Main(int argc, char** argv) {
  int vehicles = 10000, craters = 3200;
  double seconds = 20.0;
  // Light by default, as the figures of docs/performance.md were first taken; groups are physical
  // by default since.
  VehicleModel model = VehicleModel::kLight;
  for (int i = 1; i + 1 < argc; i += 2) {
    if (std::strcmp(argv[i], "--model") == 0) {
      const std::optional<VehicleModel> m = ParseVehicleModel(argv[i + 1]);
      if (!m) {
        std::fprintf(stderr, "--model %s: expected light or physical\n", argv[i + 1]);
        return 2;
      }
      model = *m;
    }
    if (std::strcmp(argv[i], "--vehicles") == 0) vehicles = std::atoi(argv[i + 1]);
    if (std::strcmp(argv[i], "--seconds") == 0) seconds = std::atof(argv[i + 1]);
    if (std::strcmp(argv[i], "--craters") == 0) craters = std::atoi(argv[i + 1]);
  }
  log::Init("vehicle_scale_bench", "warn");  // 2N "appeared" lines would be the bench
  // 5 km square, relief 50 m, 128 craters per km^2 (as vehicle_step_bench).
  const auto t_setup = std::chrono::steady_clock::now();
  const std::unique_ptr<Terrain> terrain = MakeGround(501, 50.0, craters);
  const DeadReckoningThresholds thresholds;  // the exercise file's defaults
  VehicleFleet own({1, 1}, *terrain, vehicles, "truck", model, 1, thresholds);
  VehicleFleet node2({1, 2}, *terrain, vehicles, "truck", model, 2, thresholds);
  VehicleFleet node3({1, 3}, *terrain, vehicles, "tank", model, 3, thresholds);
  FleetReceiver receiver({1, 1}, *terrain, thresholds);
  std::printf(
      "%d %s vehicles per node, 3 nodes, %.0f s at 30 Hz, terrain %.0f x %.0f m with %d craters "
      "(set-up %.1f s)\n",
      vehicles, std::string(VehicleModelName(model)).c_str(), seconds, terrain->ground().size_x_m(),
      terrain->ground().size_z_m(), craters, SecondsSince(t_setup));

  std::vector<double> own_advance_s, own_share_s, own_s, receive_s, settle_s, node_s;
  double first_receive_s = 0, first_settle_s = 0;
  uint64_t pdus = 0, steady_pdus = 0, first_pdus = 0;
  const int ticks = static_cast<int>(seconds * 30);
  const int warm_up = 30;  // the first second: every vehicle's first state
  const auto t_run = std::chrono::steady_clock::now();
  for (int k = 1; k <= ticks; ++k) {
    const double t = k * kTickS;
    const VehicleFleet::Times o = own.Tick(*terrain, t);
    const double own_tick_s = o.advance_s + o.share_s;
    (void)own.TakeSent();
    node2.Tick(*terrain, t);
    node3.Tick(*terrain, t);
    uint64_t n = 0;
    for (VehicleFleet* f : {&node2, &node3}) {
      for (const auto& bytes : f->TakeSent()) {
        receiver.Deliver(bytes);
        ++n;
      }
    }
    const FleetReceiver::Times r = receiver.Tick(*terrain, t);
    pdus += n;
    if (k == 1) {
      first_receive_s = r.receive_s;
      first_settle_s = r.settle_s;
      first_pdus = n;
    }
    if (k > warm_up) {
      steady_pdus += n;
      own_s.push_back(own_tick_s);
      own_advance_s.push_back(o.advance_s);
      own_share_s.push_back(o.share_s);
      receive_s.push_back(r.receive_s);
      settle_s.push_back(r.settle_s);
      node_s.push_back(own_tick_s + r.receive_s + r.settle_s);
    }
  }
  const double run_s = SecondsSince(t_run);
  const size_t remote = receiver.sharing().remote().vehicles().size();
  if (remote != static_cast<size_t>(2 * vehicles)) {
    std::printf("ERROR: the receiver holds %zu remote vehicles, not %d\n", remote, 2 * vehicles);
    return 1;
  }
  std::printf(
      "receiver holds %zu remote vehicles; first tick: %llu PDUs, receive %.2f ms, settle "
      "%.2f ms\n",
      remote, static_cast<unsigned long long>(first_pdus), first_receive_s * 1e3,
      first_settle_s * 1e3);
  const double steady_s = (ticks - warm_up) * kTickS;
  const double rate = static_cast<double>(steady_pdus) / steady_s;
  std::printf(
      "PDU rate of %d wandering vehicles (after the first second): %.0f PDUs/s, %.3f per "
      "vehicle per s, %.4f of one per tick; %.1f per tick\n",
      2 * vehicles, rate, rate / (2 * vehicles), rate / (2 * vehicles) / 30.0,
      static_cast<double>(steady_pdus) / (ticks - warm_up));
  std::printf("per tick, CPU time of the bench's one thread, %d ticks after the first second:\n",
              ticks - warm_up);
  Print("receiver: decode + validate + apply", Summarise(receive_s));
  Print("receiver: dead reckon + settle 2N", Summarise(settle_s));
  std::vector<double> rx(receive_s.size());
  for (size_t i = 0; i < rx.size(); ++i) rx[i] = receive_s[i] + settle_s[i];
  Print("receiver path (the two above)", Summarise(rx));
  Print("own N: wander + advance", Summarise(own_advance_s));
  Print("own N: dead-reckoning bookkeeping + send", Summarise(own_share_s));
  Print("own N vehicles (the two above)", Summarise(own_s));
  Print("node 1 whole (own + receiver path)", Summarise(node_s));
  std::printf("(%llu PDUs in all; run %.1f s wall for every fleet)\n",
              static_cast<unsigned long long>(pdus), run_s);
  return 0;
}

}  // namespace
}  // namespace dt::bench

int main(int argc, char** argv) { return dt::bench::Main(argc, argv); }
