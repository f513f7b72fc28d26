#include "dis/gateway_core.h"

#include <fmt/format.h>

#include <cctype>
#include <cmath>
#include <numbers>

#include "dis/entity_translation.h"
#include "log/log.h"
#include "pdu/dis_time.h"
#include "runtime/vehicle_listing.h"
#include "vehicle/dead_reckoning.h"

namespace dt::dis {
namespace {

// A destroyed feature's deactivated Object State is sent at once and then with the next
// periodic sends, so a receiver that lost one still learns of the removal.
constexpr int kRemovalResends = 2;
// Warnings about outside input at most this often.
constexpr double kErrorLogPeriodS = 5.0;
constexpr double kRadToDeg = 180.0 / std::numbers::pi;

// The clock is read for every PDU: a DIS time stamp says when its data held, in units of
// 1.68 us, and a stamp kept for a batch or a tick would date later PDUs too early (by up to a
// tick: tens of ms, far beyond the unit). It costs one vDSO clock read.
PduContext Context(uint8_t exercise_id) { return {exercise_id, DisTimestampNow()}; }

// The received state dead reckoned to `dt_s` after it was received.
VehicleStateFields ExtrapolatedTo(const VehicleStateFields& s, double dt_s) {
  VehicleStateFields t = s;
  const DrPose p = Extrapolate(s, dt_s);
  t.location_m = p.location_m;
  t.heading_rad = p.heading_rad;
  t.pitch_rad = p.pitch_rad;
  t.roll_rad = p.roll_rad;
  for (int i = 0; i < 3; ++i) t.velocity_mps[i] += s.acceleration_mps2[i] * dt_s;
  if (s.algorithm == dt::DeadReckoningAlgorithm::kStatic ||
      s.algorithm == dt::DeadReckoningAlgorithm::kFpw ||
      s.algorithm == dt::DeadReckoningAlgorithm::kRpw) {
    t.velocity_mps = s.velocity_mps;  // constant-velocity algorithms
  }
  return t;
}

}  // namespace

GatewayCore::GatewayCore(GatewaySettings settings, SendDatagram send, PublishVehicle publish,
                         FeatureAuthor author)
    : settings_(std::move(settings)),
      frame_(settings_.origin, settings_.ground),
      send_(std::move(send)),
      publish_(std::move(publish)),
      author_(std::move(author)),
      decoder_(settings_.exercise_id),
      members_(settings_.members.begin(), settings_.members.end()) {}

bool GatewayCore::Emit(std::span<const uint8_t> pdu) {
  const size_t max = settings_.bundle_max_bytes;
  if (max == 0 || pdu.size() > max) {
    if (!send_(pdu)) {
      ++counters_.send_failed;
      return false;
    }
    ++counters_.datagrams_sent;
    return true;
  }
  if (bundle_.size() + pdu.size() > max) Flush();
  bundle_.insert(bundle_.end(), pdu.begin(), pdu.end());
  ++bundled_pdus_;
  return true;
}

void GatewayCore::Flush() {
  if (bundle_.empty()) return;
  if (send_(bundle_)) {
    ++counters_.datagrams_sent;
  } else {
    counters_.send_failed += bundled_pdus_;
  }
  bundle_.clear();  // keeps its capacity: no allocation per bundle
  bundled_pdus_ = 0;
}

void GatewayCore::SendVehicle(OutVehicle& v, const VehicleStateFields& state, double now_s) {
  // The angles' cosines and sines serve the DIS orientation and the dead-reckoning matrix.
  const AttitudeTrig trig = TrigOf({state.heading_rad, state.pitch_rad, state.roll_rad});
  const Result<EntityStatePdu> pdu =
      EntityStateOfVehicle(state, trig, frame_, Context(settings_.exercise_id));
  if (!pdu.ok()) {
    // Not sent, so still due: the next state of the vehicle is tried again.
    ++counters_.entity_states_unmapped;
    if (now_s - last_error_log_s_ > kErrorLogPeriodS) {
      last_error_log_s_ = now_s;
      DT_LOG_WARN("vehicle {} not sent to DIS: {} (later ones counted in status)",
                  state.id.ToString(), pdu.error().message);
    }
    return;
  }
  EncodeInto(pdu.value(), datagram_);
  if (!Emit(datagram_)) return;
  v.dr.Sent(state,
            OrientationMatrixOfTrig(trig.cos_heading, trig.sin_heading, trig.cos_pitch,
                                    trig.sin_pitch, trig.cos_roll, trig.sin_roll),
            now_s);
  ++counters_.entity_state_sent;
}

void GatewayCore::OnVehicleState(NodeAddress sender, const VehicleStateFields& state,
                                 double now_s) {
  if (sender == settings_.self) return;  // what the gateway imported: DIS has it already
  auto it = vehicles_.find(state.id);
  if (it != vehicles_.end() && it->second.owner != sender) {
    ++counters_.vehicle_conflicts;  // the first sender holds the ID until it times out
    return;
  }
  if ((state.appearance & appearance::kDeactivated) != 0) {
    if (it == vehicles_.end()) return;
    // The DIS state bit is the same bit 23: the entity's last Entity State says it left.
    SendVehicle(it->second, state, now_s);
    ++counters_.entity_removals_sent;
    vehicles_.erase(it);
    return;
  }
  if (it == vehicles_.end()) {
    it = vehicles_
             .emplace(state.id,
                      OutVehicle{sender, state, now_s, DeadReckoningOwner(settings_.thresholds)})
             .first;
  }
  OutVehicle& v = it->second;
  ++v.updates;
  v.state = state;
  v.received_s = now_s;
  if (v.dr.Due(state, now_s)) SendVehicle(v, state, now_s);
}

bool GatewayCore::SendObject(const ObjectStatePdu& pdu) {
  const std::vector<uint8_t> bytes = std::visit([](const auto& p) { return Encode(p); }, pdu);
  if (!Emit(bytes)) return false;
  if (std::holds_alternative<PointObjectStatePdu>(pdu)) {
    ++counters_.point_sent;
  } else {
    ++counters_.linear_sent;
  }
  return true;
}

void GatewayCore::SendFeature(const FeatureId& id, OutFeature& f, const Terrain& terrain,
                              double now_s, bool changed) {
  const double ground = terrain.GroundElevationAt(f.params.x_m, f.params.z_m);
  // Update numbers count the object's state transitions (1, 2, ...; 0 is never used): a
  // periodic resend of an unchanged state carries the same number.
  const uint16_t next = !changed                    ? f.update_number
                        : f.update_number == 0xFFFF ? 1
                                                    : f.update_number + 1;
  Result<ObjectStatePdu> pdu =
      FeatureToDis(id, f.params, ground, next, frame_, Context(settings_.exercise_id));
  if (!pdu.ok()) {
    f.unmapped = true;
    ++counters_.features_unmapped;
    DT_LOG_WARN("feature {} is not sent to DIS: {}", id.ToString(), pdu.error().message);
    return;
  }
  f.update_number = next;
  f.sent_s = now_s;
  sends_.emplace_back(now_s, id);
  f.last = pdu.value();
  (void)SendObject(f.last);
}

void GatewayCore::Tick(const std::map<FeatureId, FeatureParams>& live, const Terrain& terrain,
                       double now_s) {
  std::vector<FeatureUpdate> updates;
  for (const auto& [id, params] : live) {
    auto it = features_.find(id);
    if (it == features_.end() || it->second.params != params) updates.push_back({id, params});
  }
  for (const auto& [id, f] : features_) {
    if (!live.count(id)) updates.push_back({id, std::nullopt});
  }
  Tick(updates, terrain, now_s);
}

void GatewayCore::Tick(std::span<const FeatureUpdate> updates, const Terrain& terrain,
                       double now_s) {
  for (auto it = vehicles_.begin(); it != vehicles_.end();) {
    OutVehicle& v = it->second;
    if (now_s - v.received_s > settings_.thresholds.timeout_s()) {
      ++counters_.vehicles_timed_out;  // DIS receivers time it out as well
      it = vehicles_.erase(it);
      continue;
    }
    const VehicleStateFields now = ExtrapolatedTo(v.state, now_s - v.received_s);
    if (v.dr.Due(now, now_s)) SendVehicle(v, now, now_s);
    ++it;
  }
  for (auto it = imported_.begin(); it != imported_.end();) {
    it = now_s - it->second.heard_s > settings_.thresholds.timeout_s() ? imported_.erase(it)
                                                                       : std::next(it);
  }

  for (const FeatureUpdate& u : updates) {
    if (OriginOf(u.id) == settings_.self) continue;  // an imported crater: DIS has its own object
    auto it = features_.find(u.id);
    if (u.params) {
      if (it == features_.end()) {
        it = features_.emplace(u.id, OutFeature{*u.params, 0, 0.0, {}, false}).first;
        SendFeature(u.id, it->second, terrain, now_s, true);
      } else if (it->second.params != *u.params) {
        it->second.params = *u.params;
        it->second.unmapped = false;
        SendFeature(u.id, it->second, terrain, now_s, true);
      }
      continue;
    }
    if (it == features_.end()) continue;
    if (!it->second.unmapped) {
      const uint16_t next = it->second.update_number == 0xFFFF ? 1 : it->second.update_number + 1;
      Removal r{Deactivated(it->second.last, next, Context(settings_.exercise_id)), next,
                kRemovalResends, now_s + settings_.feature_period_s};
      if (SendObject(r.pdu)) ++counters_.object_removals_sent;
      removals_[it->first] = std::move(r);
    }
    features_.erase(it);
  }
  for (size_t sent = 0;
       !sends_.empty() && sends_.front().first + settings_.feature_period_s <= now_s;) {
    const auto [sent_s, id] = sends_.front();
    sends_.pop_front();
    auto it = features_.find(id);
    if (it == features_.end() || it->second.unmapped || it->second.sent_s != sent_s) continue;
    SendFeature(id, it->second, terrain, now_s, false);
    if (++sent == settings_.heartbeats_per_tick_max) break;
  }
  for (auto it = removals_.begin(); it != removals_.end();) {
    Removal& r = it->second;
    if (now_s < r.next_s) {
      ++it;
      continue;
    }
    r.pdu = Deactivated(r.pdu, r.update_number, Context(settings_.exercise_id));
    if (SendObject(r.pdu)) ++counters_.object_removals_sent;
    r.next_s = now_s + settings_.feature_period_s;
    it = --r.resends_left <= 0 ? removals_.erase(it) : std::next(it);
  }
  Flush();
}

void GatewayCore::OnDatagram(std::span<const uint8_t> datagram, double now_s) {
  decoder_.DecodeBundle(datagram, [&](const DecodeResult& r) {
    if (r.ok()) {
      OnPdu(r.pdu(), now_s);
    } else if (now_s - last_error_log_s_ > kErrorLogPeriodS) {
      last_error_log_s_ = now_s;
      DT_LOG_WARN("DIS PDU dropped: {} (later ones counted in status)", r.error().message);
    }
  });
}

void GatewayCore::OnPdu(const Pdu& pdu, double now_s) {
  if (const auto* es = std::get_if<EntityStatePdu>(&pdu)) {
    OnEntityState(*es, now_s);
  } else if (const auto* point = std::get_if<PointObjectStatePdu>(&pdu)) {
    OnPointObject(*point);
  } else {
    const auto& linear = std::get<LinearObjectStatePdu>(pdu);
    if (Own(linear.object_id)) {
      ++counters_.own_dropped;
    } else {
      ++counters_.objects_ignored;  // berms and ditches are not imported
    }
  }
}

void GatewayCore::OnEntityState(const EntityStatePdu& pdu, double now_s) {
  if (Own(pdu.entity_id)) {
    ++counters_.own_dropped;
    return;
  }
  Result<VehicleStateFields> s =
      VehicleOfEntityState(pdu, frame_, settings_.terrain_size_x_m, settings_.terrain_size_z_m);
  if (!s.ok()) {
    ++counters_.entities_unmapped;
    if (now_s - last_error_log_s_ > kErrorLogPeriodS) {
      last_error_log_s_ = now_s;
      DT_LOG_WARN("outside Entity State not imported: {}", s.error().message);
    }
    return;
  }
  if (Status p = publish_(s.value()); !p.ok()) {
    ++counters_.publish_failed;
    if (now_s - last_error_log_s_ > kErrorLogPeriodS) {
      last_error_log_s_ = now_s;
      DT_LOG_WARN("outside entity {} not published: {}", s.value().id.ToString(),
                  p.error().message);
    }
    return;
  }
  ++counters_.vehicles_published;
  if ((s.value().appearance & appearance::kDeactivated) != 0) {
    imported_.erase(s.value().id);
  } else {
    Imported& held = imported_[s.value().id];
    held.state = std::move(s).value();  // published already: the state is not needed here again
    held.heard_s = now_s;
    ++held.published;
  }
}

void GatewayCore::OnPointObject(const PointObjectStatePdu& pdu) {
  if (Own(pdu.object_id)) {
    ++counters_.own_dropped;
    return;
  }
  if (!settings_.import_craters || !author_.create) {
    ++counters_.objects_ignored;
    return;
  }
  Result<FeatureFromDis> f = FeatureFromDisPdu(ObjectStatePdu(pdu), frame_);
  if (!f.ok() || f.value().params.type != FeatureType::kCrater) {
    if (f.ok()) {
      ++counters_.objects_ignored;  // only craters are imported
    } else {
      ++counters_.objects_unmapped;
    }
    return;
  }
  const FeatureId outside = f.value().id;
  auto held = craters_.find(outside);
  if (f.value().deactivated) {
    if (held == craters_.end()) return;
    if (Status s = author_.destroy(held->second); !s.ok()) {
      DT_LOG_WARN("imported crater {}: not destroyed: {}", held->second.ToString(),
                  s.error().message);
    } else {
      ++counters_.craters_removed;
    }
    craters_.erase(held);
    return;
  }
  if (held != craters_.end()) return;  // a heartbeat (a crater, once made, does not change)
  Result<FeatureId> made = author_.create(f.value().params);
  if (!made.ok()) {
    ++counters_.crater_import_failed;
    DT_LOG_WARN("crater from DIS object {} not made: {}", outside.ToString(), made.error().message);
    return;
  }
  craters_[outside] = made.value();
  ++counters_.craters_imported;
  DT_LOG_INFO("crater from DIS object {} made as {}", outside.ToString(), made.value().ToString());
}

std::string GatewayCore::VehiclesText(double now_s) const {
  std::string s;
  auto line = [&](const VehicleStateFields& state, double dt_s, ListedVehicle v) {
    const VehicleStateFields now = ExtrapolatedTo(state, dt_s);
    v.entity = state.id.ToString();
    v.type = std::string(VehicleNameOfEntityType(state.type));
    v.x_m = now.location_m[0];
    v.y_m = now.location_m[1];
    v.z_m = now.location_m[2];
    v.heading_deg = now.heading_rad * kRadToDeg;
    v.pitch_deg = now.pitch_rad * kRadToDeg;
    v.roll_deg = now.roll_rad * kRadToDeg;
    v.speed_mps = std::hypot(now.velocity_mps[0], now.velocity_mps[1], now.velocity_mps[2]);
    v.alive = (state.appearance & appearance::kDamageMask) != appearance::kDestroyed;
    if (!s.empty()) s += '\n';
    s += VehicleLine(v);
  };
  size_t index = 0;
  for (const auto& [id, held] : imported_) {
    ListedVehicle v;
    v.local = true;
    v.index = index++;
    v.owner = settings_.self.ToString();
    v.sent = held.published;
    line(held.state, now_s - held.heard_s, std::move(v));
  }
  for (const auto& [id, out] : vehicles_) {
    ListedVehicle v;
    v.owner = out.owner.ToString();
    v.model_error_m =
        out.dr.PositionErrorM(ExtrapolatedTo(out.state, now_s - out.received_s), now_s);
    v.age_s = now_s - out.received_s;
    v.updates = out.updates;
    line(out.state, now_s - out.received_s, std::move(v));
  }
  return s;
}

std::string GatewayCore::StatusLines() const {
  const GatewayCounters& c = counters_;
  const DecodeCounters& d = decoder_.counters();
  std::string s = fmt::format(
      "dis_exercise_id {}\ndis_vehicles_out {}\ndis_features_out {}\ndis_entity_state_sent {}\n"
      "dis_entity_removals_sent {}\ndis_point_object_sent {}\ndis_linear_object_sent {}\n"
      "dis_object_removals_sent {}\ndis_send_failed {}\ndis_features_unmapped {}\n"
      "dis_vehicles_timed_out {}\ndis_vehicle_conflicts {}\ndis_entity_states_unmapped {}\n"
      "dis_in_entity_state {}\ndis_in_point_object {}\ndis_in_linear_object {}\n"
      "dis_in_own_dropped {}\ndis_in_entities_unmapped {}\ndis_in_vehicles_published {}\n"
      "dis_in_publish_failed {}\ndis_in_objects_ignored {}\ndis_in_objects_unmapped {}\n"
      "dis_imported_entities {}\ndis_craters_imported {}\ndis_craters_removed {}\n"
      "dis_crater_import_failed {}\ndis_in_rejected {}\ndis_datagrams_sent {}",
      settings_.exercise_id, vehicles_.size(), features_.size(), c.entity_state_sent,
      c.entity_removals_sent, c.point_sent, c.linear_sent, c.object_removals_sent, c.send_failed,
      c.features_unmapped, c.vehicles_timed_out, c.vehicle_conflicts, c.entity_states_unmapped,
      d.entity_state, d.point_object_state, d.linear_object_state, c.own_dropped,
      c.entities_unmapped, c.vehicles_published, c.publish_failed, c.objects_ignored,
      c.objects_unmapped, imported_.size(), c.craters_imported, c.craters_removed,
      c.crater_import_failed, d.rejected_total(), c.datagrams_sent);
  for (size_t i = 0; i < kDecodeFailureCount; ++i) {
    std::string key(DecodeFailureName(static_cast<DecodeFailure>(i)));
    for (char& ch : key) ch = ch == ' ' ? '_' : static_cast<char>(std::tolower(ch));
    s += fmt::format("\ndis_in_rejected_{} {}", key, d.rejected[i]);
  }
  return s;
}

}  // namespace dt::dis
