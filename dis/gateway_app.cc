#include "dis/gateway_app.h"

#include <stdexcept>

#include <fmt/format.h>

#include "log/log.h"
#include "pdu/conversion.h"
#include "pdu/vehicle_state.h"
#include "runtime/vehicle_listing.h"

namespace dt::dis {
namespace {

const DisConfig& FindDis(const ExerciseConfig& exercise, const std::string& name) {
  if (!exercise.dis || exercise.dis->process.name != name) {
    throw std::invalid_argument(
        fmt::format("{}: no [dis] named \"{}\"", exercise.source.string(), name));
  }
  return *exercise.dis;
}

GatewaySettings SettingsOf(const ExerciseConfig& exercise, const DisConfig& dis) {
  GatewaySettings s;
  s.origin = {dis.latitude_deg, dis.longitude_deg, dis.height_m};
  if (exercise.elevation) s.ground = exercise.elevation->layout.georeference;
  s.exercise_id = dis.dis_exercise_id;
  s.thresholds = exercise.dead_reckoning;
  s.terrain_size_x_m = exercise.terrain_size_x_m();
  s.terrain_size_z_m = exercise.terrain_size_z_m();
  s.feature_period_s = dis.feature_period_ms / 1000.0;
  s.import_craters = dis.import_craters;
  s.bundle_max_bytes = static_cast<size_t>(dis.bundle_max_bytes);
  s.self = dis.process.address;
  for (const ProcessConfig* p : exercise.Processes()) s.members.insert(p->address);
  if (exercise.view) s.members.insert(exercise.view->process.address);
  s.members.insert(dis.process.address);
  return s;
}

double Seconds(int64_t ms) { return static_cast<double>(ms) / 1000.0; }

}  // namespace

// It authors the imported craters as a node member; it observes otherwise.
GatewayApp::GatewayApp(const ExerciseConfig& exercise, const std::string& name)
    : ObserverProcess(
          exercise, FindDis(exercise, name).process,
          FindDis(exercise, name).import_craters ? NodeRole::kNode : NodeRole::kObserver),
      dis_(FindDis(exercise, name)) {
  socket_ =
      std::make_unique<UdpEndpoint>(UdpEndpointConfig{.bind_address = dis_.bind_address,
                                                      .port = dis_.udp_port,
                                                      .destination = dis_.destination,
                                                      .interface_address = dis_.interface_address,
                                                      .multicast_ttl = dis_.multicast_ttl});
  FeatureAuthor author;
  if (role() == NodeRole::kNode) {
    author.create = [this](const FeatureParams& p) { return replica_->Create(p); };
    author.destroy = [this](FeatureId id) { return replica_->Destroy(id); };
  }
  core_ = std::make_unique<GatewayCore>(
      SettingsOf(exercise, dis_), [this](std::span<const uint8_t> d) { return socket_->Send(d); },
      [this](const VehicleStateFields& s) -> Status {
        if (auto r = transport_.bus->Publish(ToVehicleState(s)); !r) return r.error();
        return Status();
      },
      std::move(author));
  // Validated and authenticated by the bus like every PDU; its own are dropped there.
  transport_.bus->Subscribe<dtpdu::vehicle_state_t>([this](const dtpdu::vehicle_state_t& pdu) {
    core_->OnVehicleState(FromPdu(pdu.sender), FromVehicleState(pdu), Seconds(now_ms()));
  });
  DT_LOG_INFO(
      "DIS exercise {} on UDP {}:{} -> {} ({}), origin {:.6f} deg, {:.6f} deg, {} m, {}, {}",
      dis_.dis_exercise_id, dis_.bind_address, dis_.udp_port, dis_.destination,
      socket_->multicast() ? "multicast" : "broadcast", dis_.latitude_deg, dis_.longitude_deg,
      dis_.height_m, role() == NodeRole::kNode ? "importing craters (a node member)" : "observer",
      dis_.bundle_max_bytes == 0
          ? std::string("one PDU per datagram")
          : fmt::format("PDUs bundled up to {} bytes a datagram", dis_.bundle_max_bytes));
}

GatewayApp::~GatewayApp() = default;

void GatewayApp::OnTick(int64_t now_ms) {
  DrainDis(now_ms);
  // Every record once, then only those the replica touched: a scan of 10^6 records a tick
  // would leave no time for anything else.
  std::vector<GatewayCore::FeatureUpdate> updates;
  const auto update_of = [](FeatureId id, const Record& r) {
    return GatewayCore::FeatureUpdate{
        id, !r.destroyed && r.placed ? std::optional(r.params) : std::nullopt};
  };
  if (!tracking_) {
    replica_->TrackTouchedFeatures();
    tracking_ = true;
    for (const auto& [id, r] : replica_->records().all()) updates.push_back(update_of(id, r));
  } else {
    for (FeatureId id : replica_->TakeTouchedFeatures()) {
      const Record* r = replica_->records().Find(id);
      updates.push_back(r != nullptr ? update_of(id, *r) : GatewayCore::FeatureUpdate{id, {}});
    }
  }
  core_->Tick(updates, replica_->terrain(), Seconds(now_ms));
}

void GatewayApp::AddPollFds(std::vector<pollfd>& fds) const {
  fds.push_back({socket_->fd(), POLLIN, 0});
}

void GatewayApp::DrainDis(int64_t now_ms) {
  // Bounded per call so a flood cannot starve the bus and the control socket.
  for (int i = 0; i < 4096; ++i) {
    const auto datagram = socket_->Receive();
    if (!datagram) break;
    core_->OnDatagram(*datagram, Seconds(now_ms));
  }
}

void GatewayApp::OnWoken(int64_t now_ms) {
  DrainDis(now_ms);
  // The bus was handled before: the Entity States of the states it brought leave together.
  core_->Flush();
}

std::optional<ControlReply> GatewayApp::HandleOwn(const ControlCommand& command) {
  if (command.verb != ControlVerb::kVehicles) return std::nullopt;
  return ControlReply::Ok(
      PageVehicleListing(core_->VehiclesText(Seconds(MonotonicMs())), command.vehicle_page));
}

std::string GatewayApp::RefusalText() const {
  return "the DIS gateway runs no feature commands and drives no vehicles (send them to a node)";
}

std::string GatewayApp::StopSummary() const {
  const GatewayCounters& c = core_->counters();
  return fmt::format("{} Entity States and {} Object States sent, {} entities imported",
                     c.entity_state_sent, c.point_sent + c.linear_sent, c.vehicles_published);
}

}  // namespace dt::dis
