// VehicleFleet and FleetReceiver: the set-up of the shared-vehicle scale and accuracy benchmarks
// (docs/performance.md "Shared vehicles at scale"). A fleet is one node's wandering vehicles and
// its VehicleSharing on a private memq transport; the VehicleState PDUs it sends are kept as
// bytes, so a bench decides which reach the receiver (all, or a seeded 70 %) and times the
// receiver alone.
#pragma once

#include <chrono>
#include <cstdint>
#include <ctime>
#include <memory>
#include <span>
#include <vector>

#include "node/vehicle_sharing.h"
#include "terrain/random_terrain.h"
#include "terrain/terrain.h"
#include "transport/transport.h"
#include "vehicle/physical_type.h"
#include "vehicle/shipped_friction.h"
#include "vehicle/wander.h"

namespace dt::bench {

inline constexpr uint8_t kExercise = 1;
inline constexpr double kTickS = 1.0 / 30.0;

inline PduBusConfig BusConfig(NodeAddress local, const HeightGrid& ground) {
  PduBusConfig c;
  c.exercise_id = kExercise;
  c.local = local;
  c.terrain_size_x_m = ground.size_x_m();
  c.terrain_size_z_m = ground.size_z_m();
  return c;
}

inline double SecondsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// CPU time of the calling thread: what one core spends, whatever else the machine runs.
inline double ThreadCpuS() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + static_cast<double>(ts.tv_nsec) * 1e-9;
}

// Rolling ground (value noise, `relief_m`) of `posts` posts at 10 m with `craters` craters of
// radius 2-10 m at seeded places: what remote vehicles are settled on.
inline std::unique_ptr<Terrain> MakeGround(int posts, double relief_m, int craters) {
  RandomTerrainParams p;
  p.posts_x = p.posts_z = posts;
  p.spacing_m = 10.0;
  p.relief_m = relief_m;
  p.seed = 11;
  auto terrain = std::make_unique<Terrain>(MakeRandomTerrain(p));
  WanderRandom r(99);
  const double size_x_m = terrain->ground().size_x_m(), size_z_m = terrain->ground().size_z_m();
  for (int i = 0; i < craters; ++i) {
    const FeatureId id{1, 1, static_cast<uint32_t>(i + 1)};
    (void)terrain->Add(id, FeatureParams::Crater(r.Uniform(20, size_x_m - 20),
                                                 r.Uniform(20, size_z_m - 20), r.Uniform(2, 10)));
  }
  return terrain;
}

class VehicleFleet {
 public:
  VehicleFleet(NodeAddress owner, const Terrain& terrain, int count, const char* type_name,
               VehicleModel model, uint64_t seed, const DeadReckoningThresholds& thresholds)
      : transport_(MakeTransport("memq://", kExercise)),
        bus_(std::make_unique<PduBus>(*transport_, BusConfig(owner, terrain.ground()))),
        sharing_(std::make_unique<VehicleSharing>(*bus_, owner, thresholds)) {
    transport_->Subscribe(PduType::kVehicleState, [this](std::span<const uint8_t> bytes) {
      sent_.emplace_back(bytes.begin(), bytes.end());
    });
    const PhysicalVehicleType type = BuiltInPhysicalType(type_name, ShippedFrictionTable()).value();
    const double size_x_m = terrain.ground().size_x_m(), size_z_m = terrain.ground().size_z_m();
    const WanderArea area{0.0, size_x_m, 0.0, size_z_m};
    for (int i = 0; i < count; ++i) {
      const uint64_t s = WanderSeed(seed, static_cast<uint64_t>(i));
      wanderers_.emplace_back(type.base, area, size_x_m, size_z_m, s);
      WanderRandom place(s + 1);
      for (;;) {
        const WanderStart at = DrawWanderStart(wanderers_.back().clear_area(), place);
        auto v = SimulatedVehicle::Make(type, terrain, at.x_m, at.z_m, at.heading_rad, model);
        if (v) {
          vehicles_.push_back(std::move(v).value());
          break;
        }
      }
      sharing_->AddLocal(vehicles_.back());
    }
  }

  // One owner tick ending at t_s: every vehicle steered by its wanderer and advanced, then the
  // states due sent (and kept for TakeSent). Answers the CPU seconds of each half.
  struct Times {
    double advance_s = 0.0, share_s = 0.0;
  };
  Times Tick(const Terrain& terrain, double t_s) {
    const double t0 = ThreadCpuS();
    for (size_t i = 0; i < vehicles_.size(); ++i) {
      SimulatedVehicle& v = vehicles_[i];
      if (v.alive()) {
        const WanderCommand c = wanderers_[i].Next(v.pose(), kTickS, terrain);
        if (c.speed_mps != v.commanded_speed_mps() ||
            c.heading_rate_rad_s != v.commanded_rate_rad_s()) {
          (void)v.Command(c.speed_mps, c.heading_rate_rad_s);
        }
      }
      (void)v.Advance(terrain, kTickS);
    }
    const double t1 = ThreadCpuS();
    sharing_->Tick(vehicles_, terrain, t_s);
    const double t2 = ThreadCpuS();
    (void)transport_->HandleTimeout(0);  // the captures (its own bus drops the echoes)
    return {t1 - t0, t2 - t1};
  }

  const std::vector<SimulatedVehicle>& vehicles() const { return vehicles_; }
  const VehicleSharing& sharing() const { return *sharing_; }
  // The PDUs sent since the last TakeSent, as encoded.
  std::vector<std::vector<uint8_t>> TakeSent() { return std::exchange(sent_, {}); }

 private:
  std::unique_ptr<Transport> transport_;
  std::unique_ptr<PduBus> bus_;
  std::unique_ptr<VehicleSharing> sharing_;
  std::vector<SimulatedVehicle> vehicles_;
  std::vector<Wanderer> wanderers_;
  std::vector<std::vector<uint8_t>> sent_;
};

// A node with no vehicles of its own: its VehicleSharing receives what Deliver queues.
class FleetReceiver {
 public:
  FleetReceiver(NodeAddress local, const Terrain& terrain,
                const DeadReckoningThresholds& thresholds)
      : transport_(MakeTransport("memq://", kExercise)),
        bus_(std::make_unique<PduBus>(*transport_, BusConfig(local, terrain.ground()))),
        sharing_(std::make_unique<VehicleSharing>(*bus_, local, thresholds)) {}

  // Queues a PDU as the network would hand it over (not the receiver's work: outside the timing).
  void Deliver(std::span<const uint8_t> bytes) {
    (void)transport_->Publish(PduType::kVehicleState, bytes);
  }
  // The receiver's tick: decode, validate and apply what arrived, then dead reckon and settle
  // every remote vehicle on `terrain`. Answers the CPU seconds each half took.
  struct Times {
    double receive_s = 0.0, settle_s = 0.0;
  };
  Times Tick(const Terrain& terrain, double t_s) {
    Times out;
    const double t0 = ThreadCpuS();
    (void)transport_->HandleTimeout(0);
    const double t1 = ThreadCpuS();
    sharing_->Tick({}, terrain, t_s);
    out.receive_s = t1 - t0;
    out.settle_s = ThreadCpuS() - t1;
    return out;
  }
  const VehicleSharing& sharing() const { return *sharing_; }

 private:
  std::unique_ptr<Transport> transport_;
  std::unique_ptr<PduBus> bus_;
  std::unique_ptr<VehicleSharing> sharing_;
};

}  // namespace dt::bench
