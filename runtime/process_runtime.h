// Process runtime: what dt_node and dt_server share: transport, stop signals, common control
// commands (status, digest, features, render, faults) and catch-up progress.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "runtime/control_command.h"
#include "runtime/control_server.h"
#include "runtime/exercise_config.h"
#include "engine/replica.h"
#include "pdu/faulty_transport.h"
#include "pdu/pdu_bus.h"
#include "terrain/vehicle.h"

namespace dt {

// The exercise's transport wrapped in a FaultyTransport (faults from the config, changeable at
// run time by control commands) and a PduBus for this process.
struct ProcessTransport {
  FaultyTransport* faults = nullptr;  // owned by `transport`
  std::unique_ptr<Transport> transport;
  std::unique_ptr<PduBus> bus;
};
// Throws like MakeTransport.
ProcessTransport MakeProcessTransport(const ExerciseConfig& exercise, const ProcessConfig& process);

// SIGTERM and SIGINT set a flag (no SA_RESTART, so waits end early); SIGPIPE is ignored.
void InstallStopSignals();
bool StopRequested();

// Waits up to timeout_ms until the transport or the control socket has work (1 ms at most while
// the fault injector holds delayed messages, which need HandleTimeout calls to move).
void WaitForWork(int transport_fd, bool messages_held, const ControlServer& control,
                 int timeout_ms);

// Milliseconds since the first call (steady clock).
int64_t MonotonicMs();

// "key value" lines: name, address, role, signed_on, caught_up, diverged, diverged_since_ms,
// features, digest, own numbers, acknowledged sequence, counters, max_feature per origin,
// divergences, vehicles (docs/node.md "status").
std::string StatusText(const std::string& name, NodeRole role, const Replica& replica,
                       const FaultyTransport& faults, const std::vector<Vehicle>& vehicles);

// Answers status, digest, features, render, loss, partition, heal and ping; nullopt for the
// others (feature commands, quit), which the process handles itself.
std::optional<ControlReply> AnswerCommonCommand(const ControlCommand& command,
                                                const std::string& name, NodeRole role,
                                                const Replica& replica, FaultyTransport& faults,
                                                const std::vector<Vehicle>& vehicles);

// Renders the terrain and vehicles as a 512-pixel map PNG. Error if the file cannot be written
// or no renderer can be made.
Status RenderMapPng(const Terrain& terrain, const std::vector<Vehicle>& vehicles,
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
