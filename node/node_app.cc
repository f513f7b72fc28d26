#include "node/node_app.h"

#include <cstdio>
#include <stdexcept>

#include <fmt/format.h>

#include "log/log.h"
#include "runtime/control_command.h"
#include "runtime/exercise_ground.h"
#include "runtime/vehicle_listing.h"
#include "terrain/slump.h"
#include "vehicle/physical_type.h"

namespace dt {

NodeApp::NodeApp(const ExerciseConfig& exercise, const ProcessConfig& process)
    : exercise_(exercise), process_(process) {
  if (!process.scenario.empty()) {
    scenario_.emplace(LoadScenario(process.scenario, process.start_vehicle_count()));
  }
  BaseGround ground = BuildExerciseGround(exercise);
  transport_ = MakeProcessTransport(exercise, process);
  ReplicaConfig rc = MakeReplicaConfig(exercise, process, NodeRole::kNode);
  ids_ = std::make_unique<IdReservationFile>(exercise.run_dir / (process.name + ".ids"),
                                             process.address);
  rc.ids = ids_.get();
  replica_ = std::make_unique<Replica>(rc, std::move(ground), *transport_.bus);
  if (!replica_->load_status()) throw std::runtime_error(replica_->load_status().error().message);
  sharing_ =
      std::make_unique<VehicleSharing>(*transport_.bus, process.address, exercise.dead_reckoning);
  for (size_t i = 0; i < process.vehicles.size(); ++i) {
    const VehicleConfig& vc = process.vehicles[i];
    Result<int> added =
        Spawn({vc.type, vc.x_m, vc.z_m, vc.heading_rad, std::string(VehicleModelName(vc.model))});
    if (!added) {
      throw std::invalid_argument(fmt::format("{}: {} vehicle {}: {}", exercise.source.string(),
                                              process.name, i, added.error().message));
    }
  }
  for (size_t g = 0; g < process.groups.size(); ++g) SpawnGroup(g, process.groups[g]);
}

namespace {
// A vehicle type with a blade (the bulldozer) gets one, raised.
std::optional<Blade> BladeFor(std::string_view type) {
  Result<BladeSpec> blade = BladeOf(type);
  if (!blade) return std::nullopt;
  return Blade(blade.value());
}
}  // namespace

void NodeApp::SpawnGroup(size_t g, const VehicleGroupConfig& group) {
  constexpr int kPlacementTries = 100;
  Result<PhysicalVehicleType> type = BuiltInPhysicalType(group.type, *exercise_.friction);
  if (!type) throw std::invalid_argument(type.error().message);
  const HeightGrid& ground = replica_->terrain().ground();
  for (int i = 0; i < group.count; ++i) {
    const uint64_t seed = WanderSeed(group.seed, static_cast<uint64_t>(i));
    Wanderer wanderer(type.value().base, group.area, ground.size_x_m(), ground.size_z_m(), seed);
    WanderRandom place(seed + 1);
    std::optional<SimulatedVehicle> made;
    std::string last_error;
    for (int attempt = 0; attempt < kPlacementTries && !made; ++attempt) {
      const WanderStart s = DrawWanderStart(wanderer.clear_area(), place);
      Result<SimulatedVehicle> v = SimulatedVehicle::Make(type.value(), replica_->terrain(), s.x_m,
                                                          s.z_m, s.heading_rad, group.model);
      if (v) {
        made.emplace(std::move(v).value());
      } else {
        last_error = v.error().message;
      }
    }
    if (!made) {
      throw std::invalid_argument(
          fmt::format("{}: {} group {}: no place found for vehicle {} in {} tries: {}",
                      exercise_.source.string(), process_.name, g, i, kPlacementTries, last_error));
    }
    vehicles_.push_back(std::move(*made));
    blades_.push_back(BladeFor(group.type));
    autonomy_.emplace_back(std::move(wanderer));
    sharing_->AddLocal(vehicles_.back());
  }
  DT_LOG_INFO(
      "group {}: {} {} {} vehicle(s) wandering x {:.0f}..{:.0f} m, z {:.0f}..{:.0f} m "
      "(seed {})",
      g, group.count, VehicleModelName(group.model), group.type, group.area.x_min_m,
      group.area.x_max_m, group.area.z_min_m, group.area.z_max_m, group.seed);
}

int NodeApp::autonomous_count() const {
  int n = 0;
  for (const auto& a : autonomy_) n += a.has_value() ? 1 : 0;
  return n;
}

void NodeApp::Start(int64_t now_ms) {
  sign_on_ms_ = now_ms;
  replica_->SignOn(now_ms);
  DT_LOG_INFO("signing on as {} over {}", process_.address.ToString(), transport_.transport->Url());
}

void NodeApp::Tick(int64_t now_ms, double dt_s) {
  // The tick's changes (blade work, scenario steps) and vehicle states leave packed, at its end.
  PduBus::Batch batch(*transport_.bus);
  now_ms_ = now_ms;
  replica_->Tick(now_ms);
  for (size_t i = 0; i < vehicles_.size(); ++i) {
    SimulatedVehicle& v = vehicles_[i];
    // A wanderer steers until its vehicle can no longer be driven (destroyed, immobilised).
    if (autonomy_[i] && v.alive() && v.damage_name() == "none") {
      const WanderCommand c = autonomy_[i]->Next(v.pose(), dt_s, replica_->terrain());
      if (c.speed_mps != v.commanded_speed_mps() ||
          c.heading_rate_rad_s != v.commanded_rate_rad_s()) {
        (void)v.Command(c.speed_mps, c.heading_rate_rad_s);
      }
    }
    Result<VehicleEvents> r = v.Advance(replica_->terrain(), dt_s);
    if (!r) {
      DT_LOG_WARN("vehicle {} ({}): {}", i, v.type_name(), r.error().message);
      continue;
    }
    const VehicleEvents& e = r.value();
    if (e.mounted.number != 0) {
      DT_LOG_INFO("vehicle {} ({}) got on bridge {}", i, v.type_name(), e.mounted.ToString());
    }
    if (e.drove_off.number != 0) {
      DT_LOG_INFO("vehicle {} ({}) drove off bridge {}", i, v.type_name(), e.drove_off.ToString());
    }
    if (e.fell_off.number != 0) {
      DT_LOG_WARN("vehicle {} ({}) fell off bridge {}", i, v.type_name(), e.fell_off.ToString());
    }
    if (e.died)
      DT_LOG_WARN("vehicle {} ({}) destroyed: {}", i, v.type_name(), e.cause);
    else if (!e.cause.empty())
      DT_LOG_WARN("vehicle {} ({}) {}", i, v.type_name(), e.cause);
    if (blades_[i]) StepBlade(i);
  }
  sharing_->Tick(vehicles_, replica_->terrain(), static_cast<double>(now_ms) / 1000.0);
  if (!was_ready_) {
    if (ready()) {
      was_ready_ = true;
      progress_.Done(now_ms, *replica_);
      scenario_start_ms_ = now_ms;
      DT_LOG_INFO("signed on and caught up in {} ms: {} features, {} changes applied",
                  now_ms - sign_on_ms_, replica_->live_feature_count(),
                  replica_->counters().applied);
      std::printf("READY %s\n", process_.name.c_str());
      std::fflush(stdout);
    } else if (replica_->signed_on()) {
      progress_.Update(now_ms, *replica_);
    }
  }
  if (scenario_ && scenario_start_ms_ >= 0 && !scenario_->done()) {
    scenario_->Advance(static_cast<double>(now_ms - scenario_start_ms_) / 1000.0, *this);
    if (scenario_->done()) {
      DT_LOG_INFO("scenario finished ({} step(s) failed)", scenario_->failed());
    }
  }
}

void NodeApp::StepBlade(size_t i) {
  const VehiclePose pose = vehicles_[i].pose();
  const std::vector<PostDelta> deltas =
      blades_[i]->Step(replica_->terrain(), *exercise_.friction, pose.x_m, pose.z_m,
                       pose.heading_rad, vehicles_[i].type().base.length_m);
  // The tick's work as earth moves (docs/terrain.md "Blade work"): each one a change every node
  // adds to its ground.
  for (const auto& piece : SplitEarthMove(deltas)) {
    Result<FeatureId> id = replica_->Create(FeatureParams::EarthMove(piece));
    if (!id) {
      DT_LOG_WARN("vehicle {} ({}): blade work of {} posts not sent: {}", i,
                  vehicles_[i].type_name(), piece.size(), id.error().message);
      continue;
    }
    blade_post_changes_ += static_cast<int64_t>(piece.size());
  }
}

void NodeApp::Receive(int timeout_ms) {
  // Held (delayed) messages and queued writes need HandleTimeout calls even when the socket is
  // quiet.
  if (transport_.needs_handling() && timeout_ms > 1) timeout_ms = 1;
  Result<int> r = transport_.bus->HandleTimeout(timeout_ms);
  if (!r && !StopRequested()) DT_LOG_WARN("receive: {}", r.error().message);
}

ControlReply NodeApp::Handle(std::string_view line) {
  Result<ControlCommand> c = ParseControlCommand(line);
  if (!c) return ControlReply::Fail(c.error().message);
  if (c.value().verb == ControlVerb::kQuit) {
    quit_ = true;
    return ControlReply::Ok("bye");
  }
  switch (c.value().verb) {
    case ControlVerb::kVehicles:
      return ControlReply::Ok(
          PageVehicleListing(sharing_->VehiclesText(vehicles_), c.value().vehicle_page));
    case ControlVerb::kRender:  // remote vehicles too, in their owners' colours
      if (Status s =
              RenderMapPng(replica_->terrain(), sharing_->Sprites(vehicles_), c.value().path);
          !s) {
        return ControlReply::Fail(s.error().message);
      }
      return ControlReply::Ok(c.value().path);
    default:
      break;
  }
  if (auto r = AnswerCommonCommand(c.value(), process_.name, NodeRole::kNode, *replica_, transport_,
                                   vehicles_)) {
    if (c.value().verb == ControlVerb::kStatus && r->ok) {
      r->body += "\n" + sharing_->StatusLines() +
                 fmt::format("\nautonomous_vehicles {}", autonomous_count());
    }
    return *r;
  }
  ControlReply reply = RunFeatureCommand(c.value(), *this);
  DT_LOG_INFO("control \"{}\": {}", line, reply.ok ? "ok " + reply.body : reply.error);
  return reply;
}

Result<FeatureId> NodeApp::Create(const FeatureParams& params) { return replica_->Create(params); }

std::optional<FeatureParams> NodeApp::Params(FeatureId id) const {
  const Record* r = replica_->records().Find(id);
  if (r == nullptr || r->destroyed) return std::nullopt;
  return r->params;
}

Status NodeApp::Modify(FeatureId id, const FeatureParams& params) {
  return replica_->Modify(id, params);
}

Status NodeApp::Destroy(FeatureId id) { return replica_->Destroy(id); }

Result<std::vector<FeatureId>> NodeApp::Breach(FeatureId berm, double gap_start_m,
                                               double gap_width_m) {
  return replica_->Breach(berm, gap_start_m, gap_width_m);
}

Result<AppliedDrive> NodeApp::Drive(int index, double speed_mps, double heading_rate_rad_s) {
  if (index < 0 || index >= vehicle_count()) {
    return Error{
        fmt::format("vehicle {} does not exist (this node has {})", index, vehicle_count())};
  }
  SimulatedVehicle& v = vehicles_[static_cast<size_t>(index)];
  if (Status s = v.Command(speed_mps, heading_rate_rad_s); !s) return s.error();
  if (autonomy_[static_cast<size_t>(index)]) {
    autonomy_[static_cast<size_t>(index)].reset();
    DT_LOG_INFO("vehicle {} ({}) stops wandering: driven by its operator", index, v.type_name());
  }
  return AppliedDrive{v.type_name(), v.commanded_speed_mps(), v.commanded_rate_rad_s()};
}

Result<int> NodeApp::Spawn(const SpawnRequest& request) {
  const std::optional<VehicleModel> model = ParseVehicleModel(request.model);
  if (!model)
    return Error{fmt::format("vehicle model \"{}\" is neither physical nor light", request.model)};
  Result<PhysicalVehicleType> type = BuiltInPhysicalType(request.type, *exercise_.friction);
  if (!type) return type.error();
  Result<SimulatedVehicle> v = SimulatedVehicle::Make(
      type.value(), replica_->terrain(), request.x_m, request.z_m, request.heading_rad, *model);
  if (!v) return v.error();
  vehicles_.push_back(std::move(v).value());
  blades_.push_back(BladeFor(request.type));
  autonomy_.emplace_back();
  const EntityId id = sharing_->AddLocal(vehicles_.back());
  const int index = vehicle_count() - 1;
  DT_LOG_INFO("vehicle {} ({}): a {} at ({:.1f}, {:.1f}) moved by the {} model", index,
              id.ToString(), request.type, request.x_m, request.z_m, request.model);
  return index;
}

Status NodeApp::Remove(int index) {
  if (index < 0 || index >= vehicle_count()) {
    return Error{
        fmt::format("vehicle {} does not exist (this node has {})", index, vehicle_count())};
  }
  const auto i = static_cast<size_t>(index);
  sharing_->RemoveLocal(i, vehicles_[i], static_cast<double>(now_ms_) / 1000.0);
  vehicles_.erase(vehicles_.begin() + index);
  blades_.erase(blades_.begin() + index);
  autonomy_.erase(autonomy_.begin() + index);
  return {};
}

Status NodeApp::SetBlade(int index, std::optional<double> depth_m) {
  if (index < 0 || index >= vehicle_count()) {
    return Error{
        fmt::format("vehicle {} does not exist (this node has {})", index, vehicle_count())};
  }
  std::optional<Blade>& blade = blades_[static_cast<size_t>(index)];
  if (!blade) {
    return Error{fmt::format("vehicle {} is a {}, which has no blade (types with one: bulldozer)",
                             index, vehicles_[static_cast<size_t>(index)].type_name())};
  }
  if (!depth_m) {
    blade->Raise();
    return Status::Ok();
  }
  return blade->Lower(*depth_m);
}

}  // namespace dt
