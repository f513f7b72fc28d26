// Process runtime: what dt_node and dt_server share: transport, stop signals, common control
// commands (status, digest, features, render, faults) and catch-up progress.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "engine/replica.h"
#include "render/vehicle_sprite.h"
#include "runtime/control_command.h"
#include "runtime/control_server.h"
#include "runtime/exercise_config.h"
#include "runtime/status_report.h"
#include "transport/faulty_transport.h"
#include "transport/pdu_bus.h"
#include "transport/retrying_transport.h"
#include "vehicle/simulated_vehicle.h"

namespace dt {

// The exercise's transport wrapped in a FaultyTransport (faults from the config, changeable at
// run time by control commands), that in a RetryingTransport (a write the carrier refuses is
// queued and retried, never waited for), and a PduBus for this process over the whole stack.
// The retrying layer is outermost so it also retries writes that fail in any layer below it.
struct ProcessTransport {
  FaultyTransport* faults = nullptr;      // owned by `transport`
  RetryingTransport* retrying = nullptr;  // owned by `transport`: it is the outermost layer
  std::unique_ptr<Transport> transport;
  std::unique_ptr<PduBus> bus;
  // Held (delayed) messages and queued writes need HandleTimeout calls even while the fd is
  // quiet.
  bool needs_handling() const { return faults->held() > 0 || retrying->queued() > 0; }
};
// The layers every process puts over its carrier: faults -> retrying -> bus (bus.local is the
// process's address). The faults' delays count milliseconds.
ProcessTransport StackTransport(std::unique_ptr<Transport> carrier, const FaultConfig& faults,
                                uint64_t fault_seed, const PduBusConfig& bus);
// PDUs are authenticated with the exercise's key ([auth]); a keyless exercise logs a warning.
// Throws like MakeTransport.
ProcessTransport MakeProcessTransport(const ExerciseConfig& exercise, const ProcessConfig& process);

// The replica settings of one process: its address and role, the exercise's protocol timing,
// and every process of the exercise file as a member (docs/protocol.md, "Rules for what is
// believed"). Stores and reservations are the caller's to add.
ReplicaConfig MakeReplicaConfig(const ExerciseConfig& exercise, const ProcessConfig& process,
                                NodeRole role);

// SIGTERM and SIGINT set a flag (no SA_RESTART, so waits end early); SIGPIPE is ignored.
void InstallStopSignals();
bool StopRequested();

// Waits up to timeout_ms until the transport or the control socket has work (1 ms at most while
// needs_handling: delayed messages and queued writes need HandleTimeout calls to move).
void WaitForWork(int transport_fd, bool needs_handling, const ControlServer& control,
                 int timeout_ms);

// Milliseconds since the first call (steady clock).
int64_t MonotonicMs();

// The `status` reply of a process: its replica's state and counters, its transport's fault,
// write-retry, rejection and authentication counters, and its vehicles.
StatusReport MakeStatusReport(const std::string& name, NodeRole role, const Replica& replica,
                              const ProcessTransport& transport,
                              const std::vector<SimulatedVehicle>& vehicles);
// Its text (runtime/status_report.h defines the format; docs/node.md "status").
std::string StatusText(const std::string& name, NodeRole role, const Replica& replica,
                       const ProcessTransport& transport,
                       const std::vector<SimulatedVehicle>& vehicles);

// Answers status, digest, features, render, loss, partition, heal and ping; nullopt for the
// others (feature commands, quit), which the process handles itself.
std::optional<ControlReply> AnswerCommonCommand(const ControlCommand& command,
                                                const std::string& name, NodeRole role,
                                                const Replica& replica, ProcessTransport& transport,
                                                const std::vector<SimulatedVehicle>& vehicles);

// The longer side of a process's map render (`render`), pixels.
inline constexpr int kMapRenderPx = 512;

// Renders the whole terrain and the vehicles as a map PNG whose longer side is kMapRenderPx (the
// other follows the terrain's aspect), every vehicle at least two pixels long and wide. Error if
// the file cannot be written or no renderer can be made.
Status RenderMapPng(const Terrain& terrain, const std::vector<SimulatedVehicle>& vehicles,
                    const std::string& path);
// The same with the sprites given (a node's own and remote vehicles in their owners' colours).
Status RenderMapPng(const Terrain& terrain, const std::vector<VehicleSprite>& sprites,
                    const std::string& path);

// Reports a long catch-up: a rewritten line on a terminal, a log line every few seconds
// otherwise; nothing for catch-ups that end quickly.
class CatchUpProgress {
 public:
  CatchUpProgress();
  void Update(int64_t now_ms, const Replica& replica);
  void Done(int64_t now_ms, const Replica& replica);

 private:
  bool tty_;
  int64_t started_ms_ = -1;
  int64_t last_ms_ = -1;
  bool shown_ = false;
};

}  // namespace dt
