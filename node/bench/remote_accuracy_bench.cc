// Accuracy of shared vehicles (docs/performance.md "Shared vehicles at scale"): how far a
// receiver's copy of a wandering vehicle (dead reckoned from the VehicleState PDUs it got and
// settled on its terrain) is from the owner's truth, every tick, p50 / p99, with every PDU
// delivered and with a seeded 30 % of them lost; under the light and the physical model.
//
//   remote_accuracy_bench [--vehicles N] [--seconds S] [--loss P]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "log/log.h"
#include "node/bench/vehicle_fleet.h"

namespace dt::bench {
namespace {

double Percentile(std::vector<double>& v, double p) {
  if (v.empty()) return 0.0;
  const size_t k = std::min(v.size() - 1, static_cast<size_t>(p * static_cast<double>(v.size())));
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
  return v[k];
}

int Main(int argc, char** argv) {
  int vehicles = 300;
  double seconds = 120.0, loss = 0.3;
  for (int i = 1; i + 1 < argc; i += 2) {
    if (std::strcmp(argv[i], "--vehicles") == 0) vehicles = std::atoi(argv[i + 1]);
    if (std::strcmp(argv[i], "--seconds") == 0) seconds = std::atof(argv[i + 1]);
    if (std::strcmp(argv[i], "--loss") == 0) loss = std::atof(argv[i + 1]);
  }
  log::Init("remote_accuracy_bench", "error");  // not a line per timeout under loss
  // 2 km square, relief 30 m, 128 craters per km^2.
  const std::unique_ptr<Terrain> terrain = MakeGround(201, 30.0, 512);
  const DeadReckoningThresholds thresholds;
  std::printf(
      "%d wandering trucks per model, %.0f s at 30 Hz, thresholds %.1f m / %.0f deg / %.0f "
      "s heartbeat, %s; error sampled every tick after the first second\n",
      vehicles, seconds, thresholds.position_m, thresholds.orientation_deg, thresholds.heartbeat_s,
      std::string(DeadReckoningAlgorithmName(thresholds.algorithm)).c_str());
  for (VehicleModel model : {VehicleModel::kLight, VehicleModel::kPhysical}) {
    VehicleFleet owner({1, 2}, *terrain, vehicles, "truck", model, 21, thresholds);
    FleetReceiver all({1, 1}, *terrain, thresholds), lossy({1, 3}, *terrain, thresholds);
    WanderRandom drop(7);
    std::vector<double> horizontal[2], full[2];
    uint64_t sent = 0, delivered_lossy = 0, missing[2] = {0, 0};
    const int ticks = static_cast<int>(seconds * 30);
    for (int k = 1; k <= ticks; ++k) {
      const double t = k * kTickS;
      owner.Tick(*terrain, t);
      for (const auto& bytes : owner.TakeSent()) {
        ++sent;
        all.Deliver(bytes);
        if (drop.Uniform(0.0, 1.0) >= loss) {
          lossy.Deliver(bytes);
          ++delivered_lossy;
        }
      }
      all.Tick(*terrain, t);
      lossy.Tick(*terrain, t);
      if (k <= 30) continue;
      for (size_t i = 0; i < owner.vehicles().size(); ++i) {
        const VehiclePose truth = owner.vehicles()[i].pose();
        const EntityId id = owner.sharing().local_id(i);
        int r = 0;
        for (const FleetReceiver* rx : {&all, &lossy}) {
          const auto& seen = rx->sharing().remote().vehicles();
          const auto it = seen.find(id);
          if (it == seen.end()) {
            ++missing[r++];
            continue;
          }
          const auto& p = it->second.pose.location_m;
          const double dx = p[0] - truth.x_m, dz = p[2] - truth.z_m;
          const double dy = p[1] - truth.elevation_m;
          horizontal[r].push_back(std::hypot(dx, dz));
          full[r].push_back(std::sqrt(dx * dx + dy * dy + dz * dz));
          ++r;
        }
      }
    }
    std::printf(
        "%s model: %llu PDUs sent (%.3f per vehicle per s), %.1f %% delivered to the "
        "lossy receiver\n",
        std::string(VehicleModelName(model)).c_str(), static_cast<unsigned long long>(sent),
        static_cast<double>(sent) / (vehicles * seconds),
        100.0 * static_cast<double>(delivered_lossy) / static_cast<double>(sent));
    for (int r = 0; r < 2; ++r) {
      std::vector<double>& h = horizontal[r];
      std::vector<double>& f = full[r];
      const double within = static_cast<double>(
          std::count_if(h.begin(), h.end(), [&](double e) { return e <= thresholds.position_m; }));
      const double n = static_cast<double>(h.size());
      const double h50 = Percentile(h, 0.5), h99 = Percentile(h, 0.99);
      const double f50 = Percentile(f, 0.5), f99 = Percentile(f, 0.99);
      const double worst = h.empty() ? 0.0 : *std::max_element(h.begin(), h.end());
      std::printf(
          "  loss %2.0f %%: horizontal error p50 %.3f m, p99 %.3f m, max %.2f m; with "
          "elevation p50 %.3f m, p99 %.3f m; within %.1f m %.2f %% of %0.f samples; "
          "vehicle-ticks not held %llu\n",
          r == 0 ? 0.0 : loss * 100, h50, h99, worst, f50, f99, thresholds.position_m,
          100.0 * within / n, n, static_cast<unsigned long long>(missing[r]));
    }
  }
  return 0;
}

}  // namespace
}  // namespace dt::bench

int main(int argc, char** argv) { return dt::bench::Main(argc, argv); }
