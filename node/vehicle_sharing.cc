#include "node/vehicle_sharing.h"

#include <array>
#include <cmath>
#include <numbers>

#include <fmt/format.h>

#include "log/log.h"
#include "pdu/conversion.h"
#include "runtime/simulated_vehicle_sprite.h"
#include "runtime/vehicle_listing.h"
#include "vehicle/observed_motion.h"

namespace dt {
namespace {

constexpr double kRadToDeg = 180.0 / std::numbers::pi;
// Falling: the owner's ground contact sinks faster than any slope lets a vehicle drive down.
constexpr double kFallingSpeedMps = 3.0;

}  // namespace

Rgba OwnerColour(NodeAddress owner) {
  static constexpr std::array<Rgba, 8> kPalette = {{{200, 40, 40, 255},
                                                    {40, 90, 220, 255},
                                                    {40, 170, 60, 255},
                                                    {230, 160, 20, 255},
                                                    {160, 60, 200, 255},
                                                    {20, 180, 190, 255},
                                                    {230, 90, 170, 255},
                                                    {140, 110, 60, 255}}};
  return kPalette[(owner.site * 31u + owner.host) % kPalette.size()];
}

VehicleSharing::VehicleSharing(PduBus& bus, NodeAddress local, DeadReckoningThresholds thresholds)
    : bus_(bus), local_(local), thresholds_(thresholds), remote_(thresholds) {
  bus_.Subscribe<dtpdu::vehicle_state_t>([this](const dtpdu::vehicle_state_t& pdu) {
    remote_.Apply(FromPdu(pdu.sender), FromVehicleState(pdu), now_s_);
  });
}

EntityId VehicleSharing::AddLocal(const SimulatedVehicle& vehicle) {
  const std::optional<EntityType> type = EntityTypeOfVehicle(vehicle.type_name());
  Owned o{.id = {local_.site, local_.host, static_cast<uint16_t>(next_entity_)},
          .motion = {},
          .owner = DeadReckoningOwner(thresholds_),
          .last_truth = {},
          .shared = type.has_value(),
          .type = type.value_or(EntityType{}),
          .marking = fmt::format("{}-{}", vehicle.type_name(), next_entity_)};
  // Entity numbers are never reused in a run, so a removed vehicle's late PDUs name no other.
  next_entity_ = next_entity_ >= 65535 ? 1 : next_entity_ + 1;
  if (!o.shared) {
    DT_LOG_WARN("vehicle type {} has no entity type: vehicle {} is not shared", vehicle.type_name(),
                o.id.ToString());
  }
  owned_.push_back(std::move(o));
  return owned_.back().id;
}

VehicleStateFields VehicleSharing::Truth(const Owned& o, const SimulatedVehicle& v,
                                         const VehiclePose& p) const {
  VehicleStateFields s;
  s.id = o.id;
  s.force_id = 1;
  s.type = o.type;
  s.location_m = {p.x_m, p.elevation_m, p.z_m};
  s.heading_rad = std::remainder(p.heading_rad, 2 * std::numbers::pi);
  s.pitch_rad = p.pitch_rad;
  s.roll_rad = p.roll_rad;
  s.velocity_mps = o.motion.velocity_mps();
  s.acceleration_mps2 = o.motion.acceleration_mps2();
  s.angular_velocity_body_rad_s = o.motion.angular_velocity_body_rad_s();
  s.algorithm = thresholds_.algorithm;
  if (!v.alive()) s.appearance |= appearance::kDestroyed;
  if (v.damage_name() == "immobilised") s.appearance |= appearance::kMobilityKill;
  if (v.bridge().number != 0) {
    s.appearance |= appearance::kOnBridge;
  } else if (s.velocity_mps[1] < -kFallingSpeedMps) {
    s.appearance |= appearance::kFalling;
  }
  s.marking = o.marking;
  return s;
}

void VehicleSharing::Send(Owned& o, const VehicleStateFields& state, double now_s) {
  if (auto r = bus_.Publish(ToVehicleState(state)); !r) {
    ++send_failures_;
    DT_LOG_WARN("vehicle {}: state not sent: {}", o.id.ToString(), r.error().message);
    return;
  }
  o.owner.Sent(state, now_s);
  ++sent_;
}

void VehicleSharing::RemoveLocal(size_t index, const SimulatedVehicle& vehicle, double now_s) {
  Owned& o = owned_[index];
  if (o.shared) {
    VehicleStateFields gone = Truth(o, vehicle, vehicle.pose());
    gone.appearance |= appearance::kDeactivated;
    gone.velocity_mps = gone.acceleration_mps2 = gone.angular_velocity_body_rad_s = {0, 0, 0};
    Send(o, gone, now_s);
  }
  DT_LOG_INFO("vehicle {} ({}) removed", o.id.ToString(), vehicle.type_name());
  owned_.erase(owned_.begin() + static_cast<std::ptrdiff_t>(index));
}

void VehicleSharing::Tick(const std::vector<SimulatedVehicle>& local, const Terrain& terrain,
                          double now_s) {
  now_s_ = now_s;
  for (size_t i = 0; i < owned_.size() && i < local.size(); ++i) {
    Owned& o = owned_[i];
    if (!o.shared) continue;
    // The physical model's own velocities, not differences of its poses (docs/vehicles.md).
    ObserveVehicle(o.motion, local[i], now_s);
    o.last_truth = Truth(o, local[i], local[i].pose());
    if (o.owner.Due(o.last_truth, now_s)) Send(o, o.last_truth, now_s);
  }
  remote_.Tick(terrain, now_s);
}

std::string VehicleSharing::VehiclesText(const std::vector<SimulatedVehicle>& local) const {
  std::string s;
  auto line = [&](const ListedVehicle& v) {
    if (!s.empty()) s += '\n';
    s += VehicleLine(v);
  };
  for (size_t i = 0; i < owned_.size() && i < local.size(); ++i) {
    const Owned& o = owned_[i];
    const VehiclePose p = local[i].pose();
    ListedVehicle v;
    v.local = true;
    v.index = i;
    v.entity = o.id.ToString();
    v.type = local[i].type_name();
    v.owner = local_.ToString();
    v.x_m = p.x_m;
    v.y_m = p.elevation_m;
    v.z_m = p.z_m;
    v.heading_deg = p.heading_rad * kRadToDeg;
    v.pitch_deg = p.pitch_rad * kRadToDeg;
    v.roll_deg = p.roll_rad * kRadToDeg;
    v.speed_mps = p.speed_mps;
    v.alive = local[i].alive();
    v.model_error_m = o.owner.PositionErrorM(o.last_truth, now_s_);
    v.sent = o.owner.sent_count();
    line(v);
  }
  for (const auto& [id, r] : remote_.vehicles()) {
    ListedVehicle v;
    v.entity = id.ToString();
    v.type = r.type.name;
    v.owner = r.owner.ToString();
    v.x_m = r.pose.location_m[0];
    v.y_m = r.pose.location_m[1];
    v.z_m = r.pose.location_m[2];
    v.heading_deg = r.pose.heading_rad * kRadToDeg;
    v.pitch_deg = r.pose.pitch_rad * kRadToDeg;
    v.roll_deg = r.pose.roll_rad * kRadToDeg;
    v.speed_mps =
        std::hypot(r.state.velocity_mps[0], r.state.velocity_mps[1], r.state.velocity_mps[2]);
    v.alive = (r.state.appearance & appearance::kDamageMask) != appearance::kDestroyed;
    v.model_error_m = r.correction_m;
    v.settled = r.settled;
    v.age_s = now_s_ - r.received_s;
    v.updates = r.updates;
    line(v);
  }
  return s;
}

std::string VehicleSharing::StatusLines() const {
  return fmt::format(
      "local_vehicles {}\nremote_vehicles {}\nvehicle_pdus_sent {}\nvehicle_send_failures {}\n"
      "vehicle_pdus_received {}\nvehicle_conflicts {}\nvehicle_timeouts {}\nvehicle_removals {}",
      owned_.size(), remote_.vehicles().size(), sent_, send_failures_, remote_.received(),
      remote_.conflicts(), remote_.timed_out(), remote_.removed());
}

std::vector<VehicleSprite> VehicleSharing::Sprites(
    const std::vector<SimulatedVehicle>& local) const {
  std::vector<VehicleSprite> out;
  for (const SimulatedVehicle& v : local) out.push_back(SpriteOf(v, OwnerColour(local_)));
  for (const auto& [id, v] : remote_.vehicles()) {
    VehicleSprite s;
    s.x_m = v.pose.location_m[0];
    s.y_m = v.pose.location_m[1];
    s.z_m = v.pose.location_m[2];
    s.heading_rad = v.pose.heading_rad;
    s.pitch_rad = v.pose.pitch_rad;
    s.roll_rad = v.pose.roll_rad;
    s.length_m = v.type.length_m;
    s.width_m = v.type.width_m;
    s.height_m = v.type.width_m * kSpriteHeightPerWidth;
    const bool dead = (v.state.appearance & appearance::kDamageMask) == appearance::kDestroyed;
    s.colour = dead ? kDeadVehicleColour : OwnerColour(v.owner);
    out.push_back(s);
  }
  return out;
}

}  // namespace dt
