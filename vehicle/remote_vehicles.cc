#include "vehicle/remote_vehicles.h"

#include <cmath>

#include "base/demand.h"
#include "log/log.h"

namespace dt {

bool SettleOnTerrain(const Terrain& terrain, const VehicleType& type, DrPose& pose) {
  const double x = pose.location_m[0], z = pose.location_m[2];
  const double ax = std::cos(pose.heading_rad), az = std::sin(pose.heading_rad);
  const double lx = -az, lz = ax;  // left of the heading
  const double hl = type.length_m / 2, hw = type.width_m / 2;
  const double pts[4][2] = {{x + ax * hl, z + az * hl},
                            {x - ax * hl, z - az * hl},
                            {x + lx * hw, z + lz * hw},
                            {x - lx * hw, z - lz * hw}};
  for (const auto& p : pts) {
    if (!terrain.Contains(p[0], p[1])) return false;
  }
  const double front = terrain.ElevationAt(pts[0][0], pts[0][1]);
  const double back = terrain.ElevationAt(pts[1][0], pts[1][1]);
  const double left = terrain.ElevationAt(pts[2][0], pts[2][1]);
  const double right = terrain.ElevationAt(pts[3][0], pts[3][1]);
  pose.location_m[1] = (front + back + left + right) / 4;
  pose.pitch_rad = std::atan2(front - back, type.length_m);
  pose.roll_rad = std::atan2(left - right, type.width_m);  // right side down is positive
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
    // Off the ground (on a bridge deck, falling) the owner's elevation and tilt are kept.
    const bool grounded =
        (v.state.appearance & (appearance::kOnBridge | appearance::kFalling)) == 0;
    v.settled = grounded && SettleOnTerrain(terrain, v.type, v.pose);
    ++it;
  }
  return dropped;
}

}  // namespace dt
