#include "vehicle/remote_vehicles.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "base/demand.h"
#include "log/log.h"
#include "vehicle/bridge_solids.h"
#include "vehicle/contact_surface.h"

namespace dt {

bool SettleOnTerrain(const Terrain& terrain, const VehicleType& type, DrPose& pose) {
  const double x = pose.location_m[0], z = pose.location_m[2];
  const double ax = std::cos(pose.heading_rad), az = std::sin(pose.heading_rad);
  const double lx = -az, lz = ax;  // left of the heading
  const double hl = type.length_m / 2, hw = type.width_m / 2;
  auto at = [&](double ahead_m, double left_m) {
    return std::pair{x + ax * ahead_m + lx * left_m, z + az * ahead_m + lz * left_m};
  };
  // The footprint's corners on the terrain, so every point between them is.
  for (const double a : {-hl, hl}) {
    for (const double l : {-hw, hw}) {
      const auto [px, pz] = at(a, l);
      if (!terrain.Contains(px, pz)) return false;
    }
  }
  Rect plan{x - hl - hw, z - hl - hw, x + hl + hw, z + hl + hw};
  // This node's bridges as the solids the physical model drives on: a top within a climb of the
  // owner's elevation carries the vehicle (so a deck the owner drives on is met here, and one
  // destroyed here lets it down onto what lies below instead of leaving it in the air); a solid
  // higher up is passed under.
  std::vector<Solid> solids;
  SolidsNear(terrain, plan, solids);
  const double reach_m = pose.location_m[1] + kRemoteClimbM;
  auto surface = [&](double ahead_m, double left_m) {
    const auto [px, pz] = at(ahead_m, left_m);
    return solids.empty() ? terrain.ElevationAt(px, pz)
                          : SampleSurface(terrain, solids, px, pz, reach_m).height_m;
  };
  const double front = surface(hl, 0), back = surface(-hl, 0);
  const double left = surface(0, hw), right = surface(0, -hw);
  const double grade_ahead = (front - back) / type.length_m;
  const double grade_left = (left - right) / type.width_m;
  pose.pitch_rad = std::atan2(front - back, type.length_m);
  pose.roll_rad = std::atan2(left - right, type.width_m);  // right side down is positive
  // The plane of that tilt laid on the highest point of the surface under the footprint, sampled
  // every kRemoteSettleStepM: over a crest (a berm, a crater's rim, a solid's edge) the vehicle
  // rests on the crest, not in it. Where no earthwork or solid is near, the ground's triangles
  // are flat enough for the mean of the sides (on a plane the same).
  double y = (front + back + left + right) / 4;
  if (!solids.empty() || EarthworkNear(terrain, plan)) {
    const int n_ahead = static_cast<int>(std::ceil(type.length_m / kRemoteSettleStepM));
    const int n_left = static_cast<int>(std::ceil(type.width_m / kRemoteSettleStepM));
    auto lay = [&](double ahead_m, double left_m, double h) {
      y = std::max(y, h - ahead_m * grade_ahead - left_m * grade_left);
    };
    lay(0, 0, surface(0, 0));
    for (int i = 0; i <= n_ahead; ++i) {
      for (int k = 0; k <= n_left; ++k) {
        const double a = -hl + type.length_m * i / n_ahead, l = -hw + type.width_m * k / n_left;
        lay(a, l, surface(a, l));
      }
    }
  }
  pose.location_m[1] = y;
  return true;
}

size_t RemoteVehicles::count_owned_by(NodeAddress owner) const {
  size_t n = 0;
  for (const auto& [id, v] : vehicles_) n += v.owner == owner ? 1 : 0;
  return n;
}

RemoteApply RemoteVehicles::Apply(NodeAddress sender, const VehicleStateFields& state,
                                  double now_s) {
  ++received_;
  auto it = vehicles_.find(state.id);
  if (it != vehicles_.end() && it->second.owner != sender) {
    ++conflicts_;
    if (now_s - last_conflict_log_s_ >= 1.0) {
      DT_LOG_WARN(
          "dropped a VEHICLESTATE PDU: entity {} is held for sender {}, claimed by {}; {} more "
          "such conflicts since the last such line",
          state.id.ToString(), it->second.owner.ToString(), sender.ToString(), conflicts_unlogged_);
      last_conflict_log_s_ = now_s;
      conflicts_unlogged_ = 0;
    } else {
      ++conflicts_unlogged_;
    }
    return RemoteApply::kConflict;
  }
  if ((state.appearance & appearance::kDeactivated) != 0) {
    if (it == vehicles_.end()) return RemoteApply::kIgnored;
    DT_LOG_INFO("remote vehicle {} of {} removed by its owner", state.id.ToString(),
                sender.ToString());
    vehicles_.erase(it);
    ++removed_;
    return RemoteApply::kRemoved;
  }
  // Validation accepted only known entity types, so the name is a built-in's.
  auto type = BuiltInVehicleType(VehicleNameOfEntityType(state.type));
  DT_DEMAND(type);
  const bool added = it == vehicles_.end();
  if (added) {
    it = vehicles_.emplace(state.id, RemoteVehicle{}).first;
    it->second.id = state.id;
    it->second.owner = sender;
    DT_LOG_INFO("remote vehicle {} ({}, \"{}\") of {} appeared", state.id.ToString(),
                type.value().name, state.marking, sender.ToString());
  } else {
    const DrPose predicted =
        Extrapolate(it->second.state, it->second.orientation0, now_s - it->second.received_s);
    it->second.correction_m = PositionErrorM(predicted, PoseOf(state));
  }
  RemoteVehicle& v = it->second;
  v.state = state;
  v.orientation0 = OrientationMatrix(state.heading_rad, state.pitch_rad, state.roll_rad);
  v.received_s = now_s;
  v.type = std::move(type).value();
  v.pose = PoseOf(state);
  ++v.updates;
  return added ? RemoteApply::kAdded : RemoteApply::kUpdated;
}

std::vector<EntityId> RemoteVehicles::Tick(const Terrain& terrain, double now_s) {
  std::vector<EntityId> dropped;
  for (auto it = vehicles_.begin(); it != vehicles_.end();) {
    RemoteVehicle& v = it->second;
    const double silent_s = now_s - v.received_s;
    if (silent_s > thresholds_.timeout_s()) {
      DT_LOG_WARN("remote vehicle {} of {} dropped: not heard for {:.1f} s (timeout {:.1f} s)",
                  v.id.ToString(), v.owner.ToString(), silent_s, thresholds_.timeout_s());
      dropped.push_back(v.id);
      ++timed_out_;
      it = vehicles_.erase(it);
      continue;
    }
    v.pose = Extrapolate(v.state, v.orientation0, silent_s);
    // Falling, the owner's elevation and tilt are kept; on the ground or a deck it is settled on
    // this node's terrain (SettleOnTerrain meets this node's decks).
    const bool falling = (v.state.appearance & appearance::kFalling) != 0;
    v.settled = !falling && SettleOnTerrain(terrain, v.type, v.pose);
    ++it;
  }
  return dropped;
}

}  // namespace dt
