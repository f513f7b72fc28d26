#include "dis/gateway_app.h"

#include <poll.h>

#include <algorithm>
#include <stdexcept>

#include <fmt/format.h>

#include "log/log.h"
#include "pdu/conversion.h"
#include "pdu/vehicle_state.h"
#include "runtime/control_command.h"
#include "terrain/random_terrain.h"

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
  s.exercise_id = dis.dis_exercise_id;
  s.thresholds = exercise.dead_reckoning;
  s.terrain_size_m = exercise.terrain_size_m();
  s.feature_period_s = dis.feature_period_ms / 1000.0;
  s.import_craters = dis.import_craters;
  s.self = dis.process.address;
  for (const ProcessConfig* p : exercise.Processes()) s.members.insert(p->address);
  if (exercise.view) s.members.insert(exercise.view->process.address);
  s.members.insert(dis.process.address);
  return s;
}

}  // namespace

GatewayApp::GatewayApp(const ExerciseConfig& exercise, const std::string& name)
    : exercise_(exercise),
      dis_(FindDis(exercise, name)),
      role_(dis_.import_craters ? NodeRole::kNode : NodeRole::kObserver),
      transport_(MakeProcessTransport(exercise, dis_.process)) {
  ReplicaConfig rc = MakeReplicaConfig(exercise, dis_.process, role_);
  if (role_ == NodeRole::kNode) {
    // It authors the imported craters: never reissue a number after a restart, as a node.
    ids_ = std::make_unique<IdReservationFile>(exercise.run_dir / (dis_.process.name + ".ids"),
                                               dis_.process.address);
    rc.ids = ids_.get();
  }
  replica_ = std::make_unique<Replica>(std::move(rc), MakeRandomTerrain(exercise.terrain),
                                       *transport_.bus);
  if (!replica_->load_status()) throw std::runtime_error(replica_->load_status().error().message);
  socket_ = std::make_unique<UdpEndpoint>(
      UdpEndpointConfig{dis_.bind_address, dis_.udp_port, dis_.destination, dis_.interface_address,
                        dis_.multicast_ttl});
  FeatureAuthor author;
  if (role_ == NodeRole::kNode) {
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
    core_->OnVehicleState(FromPdu(pdu.sender), FromVehicleState(pdu),
                          static_cast<double>(now_ms_) / 1000.0);
  });
  DT_LOG_INFO("DIS exercise {} on UDP {}:{} -> {} ({}), origin {:.6f} deg, {:.6f} deg, {} m, {}",
              dis_.dis_exercise_id, dis_.bind_address, dis_.udp_port, dis_.destination,
              socket_->multicast() ? "multicast" : "broadcast", dis_.latitude_deg,
              dis_.longitude_deg, dis_.height_m,
              role_ == NodeRole::kNode ? "importing craters (a node member)" : "observer");
}

GatewayApp::~GatewayApp() = default;

void GatewayApp::Start(int64_t now_ms) {
  now_ms_ = now_ms;
  replica_->SignOn(now_ms);
}

void GatewayApp::Tick(int64_t now_ms) {
  now_ms_ = now_ms;
  replica_->Tick(now_ms);
  DrainDis(now_ms);
  std::map<FeatureId, FeatureParams> live;
  for (const auto& [id, r] : replica_->records().all()) {
    if (!r.destroyed && r.placed) live.emplace(id, r.params);
  }
  core_->Tick(live, replica_->terrain(), static_cast<double>(now_ms) / 1000.0);
}

void GatewayApp::DrainDis(int64_t now_ms) {
  // Bounded per call so a flood cannot starve the bus and the control socket.
  for (int i = 0; i < 4096; ++i) {
    const auto datagram = socket_->Receive();
    if (!datagram) break;
    core_->OnDatagram(*datagram, static_cast<double>(now_ms) / 1000.0);
  }
}

void GatewayApp::Wait(const ControlServer& control, int timeout_ms) {
  std::vector<pollfd> fds = {{transport_.bus->Fd(), POLLIN, 0}, {socket_->fd(), POLLIN, 0}};
  control.AddPollFds(fds);
  ::poll(fds.data(), fds.size(),
         transport_.needs_handling() ? std::min(timeout_ms, 1) : timeout_ms);
  now_ms_ = MonotonicMs();
  (void)transport_.bus->HandleTimeout(0);
  DrainDis(now_ms_);
}

ControlReply GatewayApp::Handle(std::string_view line) {
  static const std::vector<SimulatedVehicle> kNoVehicles;  // it drives none
  Result<ControlCommand> c = ParseControlCommand(line);
  if (!c) return ControlReply::Fail(c.error().message);
  if (c.value().verb == ControlVerb::kQuit) {
    quit_ = true;
    return ControlReply::Ok("bye");
  }
  if (c.value().verb == ControlVerb::kStatus) {
    return ControlReply::Ok(
        StatusText(dis_.process.name, role_, *replica_, transport_, kNoVehicles) + "\n" +
        core_->StatusLines());
  }
  if (auto r = AnswerCommonCommand(c.value(), dis_.process.name, role_, *replica_, transport_,
                                   kNoVehicles)) {
    return *r;
  }
  return ControlReply::Fail(fmt::format(
      "\"{}\": the DIS gateway runs no feature or vehicle commands (send them to a node)", line));
}

}  // namespace dt::dis
