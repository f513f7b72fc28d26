// GatewayCore: the DIS gateway's translation without sockets or a replica (docs/dis.md "The
// gateway"): exercise vehicles and features out as Entity State and Object State PDUs under DIS
// dead reckoning and heartbeats, outside Entity States in as VehicleStates, and (when allowed)
// outside craters in as features. Datagrams and PDUs leave through the callbacks it is given.
#pragma once

#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <optional>
#include <set>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "base/feature_id.h"
#include "base/result.h"
#include "dis/dis_codec.h"
#include "dis/feature_mapping.h"
#include "dis/geodetic_frame.h"
#include "pdu/vehicle_state.h"
#include "terrain/feature_params.h"
#include "terrain/terrain.h"
#include "vehicle/dead_reckoning_policy.h"

namespace dt::dis {

struct GatewaySettings {
  GeodeticOrigin origin;
  std::shared_ptr<const GroundGeoreference> ground;  // an elevation file's; null: none
  uint8_t exercise_id = 1;  // the DIS exercise ID sent and required on input
  DeadReckoningThresholds thresholds;
  // The terrain covers [0, terrain_size_x_m] x [0, terrain_size_z_m]: outside entities beyond it
  // are refused.
  double terrain_size_x_m = 0.0;
  double terrain_size_z_m = 0.0;
  double feature_period_s = 5.0;  // every live feature's Object State again this often
  // Periodic resends a tick at most, oldest first: with more features than the period allows
  // (10^6 every 5 s would be 200 000 a second) the period stretches instead of the tick.
  size_t heartbeats_per_tick_max = 2000;
  bool import_craters = false;
  NodeAddress self;  // the gateway's own address: it owns the vehicles it imports
  // The exercise's members: DIS input whose site/application is one of them is the exercise's
  // own (the gateway's datagrams looped back, or another gateway of the same exercise).
  std::set<NodeAddress> members;
  // 0: one PDU per datagram. Else PDUs are bundled (IEEE 1278.2) into datagrams of at most this
  // many bytes, sent when the next PDU would not fit and at Flush; a PDU larger goes alone.
  size_t bundle_max_bytes = 0;
};

struct GatewayCounters {
  // Out, to DIS.
  uint64_t entity_state_sent = 0, entity_removals_sent = 0, point_sent = 0, linear_sent = 0,
           object_removals_sent = 0, send_failed = 0, features_unmapped = 0, vehicles_timed_out = 0,
           vehicle_conflicts = 0;
  // Datagrams sent (with bundling fewer than the PDUs). A PDU is counted sent once bundled; a
  // bundle the kernel refuses counts each of its PDUs in send_failed.
  uint64_t datagrams_sent = 0;
  // Exercise states with no Entity State (a value not finite or too large for the PDU): dropped.
  uint64_t entity_states_unmapped = 0;
  // In, from DIS (decode counters are the decoder's).
  uint64_t own_dropped = 0, entities_unmapped = 0, vehicles_published = 0, publish_failed = 0,
           objects_ignored = 0, objects_unmapped = 0, craters_imported = 0, craters_removed = 0,
           crater_import_failed = 0;
};

// Creates and destroys features for imported craters (the gateway's replica).
struct FeatureAuthor {
  std::function<Result<FeatureId>(const FeatureParams&)> create;
  std::function<Status(FeatureId)> destroy;
};

class GatewayCore {
 public:
  using SendDatagram = std::function<bool(std::span<const uint8_t>)>;
  using PublishVehicle = std::function<Status(const VehicleStateFields&)>;

  // Throws std::invalid_argument for a bad origin (GeodeticFrame).
  GatewayCore(GatewaySettings settings, SendDatagram send, PublishVehicle publish,
              FeatureAuthor author = {});

  // Exercise -> DIS. A VehicleState heard on the bus at now_s (never the gateway's own).
  void OnVehicleState(NodeAddress sender, const VehicleStateFields& state, double now_s);
  // A feature as the exercise holds it now: its parameters while live and placed; none once
  // gone (destroyed or not placed).
  struct FeatureUpdate {
    FeatureId id;
    std::optional<FeatureParams> params;
  };
  // Heartbeats and timeouts of the vehicles; every update that is new or changed is sent, one
  // gone is sent deactivated, and every feature not sent for the feature period is sent again.
  // `terrain` gives the bare ground under each feature. The cost follows the updates, not the
  // number of features (a large world's gateway).
  void Tick(std::span<const FeatureUpdate> updates, const Terrain& terrain, double now_s);
  // The same from the whole live set: the updates are its difference from what was sent.
  void Tick(const std::map<FeatureId, FeatureParams>& live, const Terrain& terrain, double now_s);

  // With bundling, sends the PDUs waiting in the bundle (Tick ends with it; the process calls it
  // once it has handled what woke it, so a PDU waits at most for the states heard with it).
  void Flush();

  // DIS -> exercise. One datagram received at now_s, bundling one or more PDUs: each is dropped
  // and counted unless it is whole, valid, of this DIS exercise and from outside; the others of
  // the datagram are taken all the same.
  void OnDatagram(std::span<const uint8_t> datagram, double now_s);

  const GatewayCounters& counters() const { return counters_; }
  const DecodeCounters& decode_counters() const { return decoder_.counters(); }
  size_t vehicles_out() const { return vehicles_.size(); }
  size_t features_out() const { return features_.size(); }
  size_t imported_entities() const { return imported_.size(); }
  size_t imported_craters() const { return craters_.size(); }
  const GeodeticFrame& frame() const { return frame_; }
  // "key value" lines for the control socket's status.
  std::string StatusLines() const;
  // `dt_ctl vehicles` at now_s (runtime/vehicle_listing.h, the node's format): a "local" line
  // per outside entity it imported (it owns them in the exercise: index in entity ID order,
  // model_error_m 0 since every state is published as it came, sent the states published), then
  // a "remote" line per exercise vehicle it sends to DIS (its last state dead reckoned to now_s,
  // not settled on the terrain; model_error_m how far DIS receivers' copy is off).
  std::string VehiclesText(double now_s) const;

 private:
  struct OutVehicle {
    NodeAddress owner;
    VehicleStateFields state;  // the last received
    double received_s = 0.0;
    DeadReckoningOwner dr;
    uint64_t updates = 0;  // states received
  };
  struct Imported {
    VehicleStateFields state;  // the last published
    double heard_s = 0.0;
    uint64_t published = 0;
  };
  struct OutFeature {
    FeatureParams params;
    uint16_t update_number = 0;
    double sent_s = 0.0;
    ObjectStatePdu last;
    bool unmapped = false;  // has no DIS form: never sent
  };
  struct Removal {
    ObjectStatePdu pdu;
    uint16_t update_number = 0;
    int resends_left = 0;
    double next_s = 0.0;
  };

  bool Own(const EntityId& id) const {
    const NodeAddress a{id.site, id.application};
    for (const NodeAddress& m : members_) {
      if (m == a) return true;
    }
    return false;
  }
  void SendVehicle(OutVehicle& v, const VehicleStateFields& state, double now_s);
  bool SendObject(const ObjectStatePdu& pdu);
  // One encoded PDU out: sent, or added to the bundle. False when the kernel refused it.
  bool Emit(std::span<const uint8_t> pdu);
  void OnPdu(const Pdu& pdu, double now_s);
  // changed: a new state (the update number goes up), else a periodic resend of the same.
  void SendFeature(const FeatureId& id, OutFeature& f, const Terrain& terrain, double now_s,
                   bool changed);
  void OnEntityState(const EntityStatePdu& pdu, double now_s);
  void OnPointObject(const PointObjectStatePdu& pdu);

  GatewaySettings settings_;
  GeodeticFrame frame_;
  SendDatagram send_;
  PublishVehicle publish_;
  FeatureAuthor author_;
  Decoder decoder_;
  GatewayCounters counters_;
  std::map<dt::EntityId, OutVehicle> vehicles_;
  std::map<FeatureId, OutFeature> features_;
  // Each feature's sends in time order (sent_s, id): the front is the next heartbeat due. An
  // entry older than its feature's last send is skipped when it comes up.
  std::deque<std::pair<double, FeatureId>> sends_;
  std::map<FeatureId, Removal> removals_;
  std::map<dt::EntityId, Imported> imported_;  // outside entities
  std::map<FeatureId, FeatureId> craters_;     // outside object ID -> the feature made for it
  double last_error_log_s_ = -1e300;
  // settings_.members as a flat array: an exercise has few members, and every PDU in asks.
  std::vector<NodeAddress> members_;
  std::vector<uint8_t> datagram_;  // each Entity State encoded here: no allocation per PDU
  std::vector<uint8_t> bundle_;    // PDUs waiting to be sent together
  uint64_t bundled_pdus_ = 0;      // how many PDUs bundle_ holds
};

}  // namespace dt::dis
