// NodeApp: a node process's state (replica, vehicles, scenario) and its per-tick work.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "engine/replica.h"
#include "node/scenario_runner.h"
#include "node/vehicle_sharing.h"
#include "runtime/control_protocol.h"
#include "runtime/exercise_config.h"
#include "runtime/id_reservation_file.h"
#include "runtime/node_actions.h"
#include "runtime/process_runtime.h"
#include "vehicle/blade.h"
#include "vehicle/simulated_vehicle.h"
#include "vehicle/wander.h"

namespace dt {

class NodeApp final : public NodeActions {
 public:
  // Loads the scenario (a bad one throws std::invalid_argument before anything runs), builds the
  // ground, the transport, the replica and the vehicles (each moved by the model its config names,
  // gripping by the exercise's friction table). Throws std::invalid_argument for a bad vehicle
  // placement.
  NodeApp(const ExerciseConfig& exercise, const ProcessConfig& process);

  // Signs on; the scenario starts once the node is ready (signed on and caught up).
  void Start(int64_t now_ms);
  // One loop tick: protocol timers, vehicles (their events logged), scenario. dt_s is the
  // simulated time step.
  void Tick(int64_t now_ms, double dt_s);
  // Receives PDUs for up to timeout_ms.
  void Receive(int timeout_ms);
  int transport_fd() const { return transport_.bus->Fd(); }
  bool needs_handling() const { return transport_.needs_handling(); }
  ControlReply Handle(std::string_view line);

  bool ready() const { return replica_->signed_on() && replica_->caught_up(); }
  bool quit_requested() const { return quit_; }
  const Replica& replica() const { return *replica_; }
  const std::vector<SimulatedVehicle>& vehicles() const { return vehicles_; }
  const VehicleSharing& sharing() const { return *sharing_; }
  // Vehicles still wandering (docs/vehicles.md "Autonomous groups"): a group's, until a drive
  // command hands one to its operator.
  int autonomous_count() const;
  bool autonomous(int index) const { return autonomy_[static_cast<size_t>(index)].has_value(); }

  // NodeActions.
  Result<FeatureId> Create(const FeatureParams& params) override;
  std::optional<FeatureParams> Params(FeatureId id) const override;
  Status Modify(FeatureId id, const FeatureParams& params) override;
  Status Destroy(FeatureId id) override;
  Result<std::vector<FeatureId>> Breach(FeatureId berm, double gap_start_m,
                                        double gap_width_m) override;
  int vehicle_count() const override { return static_cast<int>(vehicles_.size()); }
  Result<AppliedDrive> Drive(int index, double speed_mps, double heading_rate_rad_s) override;
  Result<int> Spawn(const SpawnRequest& request) override;
  Status Remove(int index) override;
  Status SetBlade(int index, std::optional<double> depth_m) override;
  // Posts changed by the blades since start (the earth moves this node made).
  int64_t blade_post_changes() const { return blade_post_changes_; }

 private:
  // One tick of vehicle i's blade: its post changes issued as earth moves.
  void StepBlade(size_t i);
  // Places group `g` (its vehicles appended to vehicles_, each wandering); throws
  // std::invalid_argument naming the group when no place is found for one.
  void SpawnGroup(size_t g, const VehicleGroupConfig& group);

  const ExerciseConfig& exercise_;
  const ProcessConfig& process_;
  std::optional<ScenarioRunner> scenario_;
  ProcessTransport transport_;
  std::unique_ptr<IdReservationFile> ids_;  // outlives the replica
  std::unique_ptr<Replica> replica_;
  std::vector<SimulatedVehicle> vehicles_;
  std::vector<std::optional<Wanderer>> autonomy_;  // one per vehicle: set while it wanders
  std::unique_ptr<VehicleSharing> sharing_;        // over transport_.bus; its order is vehicles_'
  std::vector<std::optional<Blade>> blades_;       // one per vehicle, in vehicles_' order
  int64_t blade_post_changes_ = 0;
  int64_t now_ms_ = 0;
  CatchUpProgress progress_;
  int64_t sign_on_ms_ = 0;
  int64_t scenario_start_ms_ = -1;
  bool was_ready_ = false;
  bool quit_ = false;
};

}  // namespace dt
