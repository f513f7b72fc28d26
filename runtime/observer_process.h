// ObserverProcess: what the exercise's observer processes (dt_view, dt_dis) share: a replica on
// the process transport, its control socket's commands, and the tick loop their mains run.
#pragma once

#include <poll.h>

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "engine/replica.h"
#include "runtime/control_command.h"
#include "runtime/control_protocol.h"
#include "runtime/control_server.h"
#include "runtime/exercise_config.h"
#include "runtime/id_reservation_file.h"
#include "runtime/process_runtime.h"

namespace dt {

// A process that holds a replica of the exercise but drives no vehicles. The concrete process
// adds its own work through the hooks; Run() is its whole life after construction.
class ObserverProcess {
 public:
  virtual ~ObserverProcess();
  ObserverProcess(const ObserverProcess&) = delete;
  ObserverProcess& operator=(const ObserverProcess&) = delete;

  // Serves the control socket, signs on, prints `ReadyLines()` and "READY <name>", then ticks
  // at the exercise's tick_hz, waiting for the bus, the process's own descriptors and the
  // control socket between ticks, until a stop signal or `quit`. Throws like ControlServer.
  void Run();

  // Signs on (the first call a test or Run makes).
  void Start(int64_t now_ms);
  // Protocol tick, then the process's own.
  void Tick(int64_t now_ms);
  // Waits up to timeout_ms for the bus, the process's descriptors or `control`, then handles
  // what the bus has and calls OnWoken.
  void Wait(const ControlServer& control, int timeout_ms);
  // quit, the process's own commands, then status, digest, features, render, faults and ping;
  // anything else is refused with RefusalText.
  ControlReply Handle(std::string_view line);

  bool quit_requested() const { return quit_; }
  const Replica& replica() const { return *replica_; }
  const ProcessConfig& process() const { return process_; }
  NodeRole role() const { return role_; }

 protected:
  // Makes the run directory, installs the stop signals and builds the transport and replica.
  // A kNode member (it authors features) gets a reservation file like a node's, so it never
  // reissues a number after a restart. Throws std::runtime_error when the replica's stores do
  // not load.
  ObserverProcess(const ExerciseConfig& exercise, const ProcessConfig& process, NodeRole role);

  virtual void OnStart(int64_t /*now_ms*/) {}
  virtual void OnTick(int64_t now_ms) = 0;
  // Descriptors the process also waits on between ticks, and what it does once woken.
  virtual void AddPollFds(std::vector<pollfd>& /*fds*/) const {}
  virtual void OnWoken(int64_t /*now_ms*/) {}
  // A command the process answers itself (before the common ones); nullopt passes it on.
  virtual std::optional<ControlReply> HandleOwn(const ControlCommand& /*command*/) {
    return std::nullopt;
  }
  // Lines appended to `status`, and why other commands are refused.
  virtual std::string StatusLines() const { return {}; }
  virtual std::string RefusalText() const = 0;
  // Printed before the READY line (one "KEY value" line each), and logged when the loop ends.
  virtual std::string ReadyLines() const { return {}; }
  virtual std::string StopSummary() const = 0;

  // When the process last started, ticked or woke (the bus's handlers see it).
  int64_t now_ms() const { return now_ms_; }

  const ExerciseConfig& exercise_;
  const ProcessConfig& process_;
  const NodeRole role_;
  ProcessTransport transport_;
  std::unique_ptr<IdReservationFile> ids_;
  std::unique_ptr<Replica> replica_;

 private:
  int64_t now_ms_ = 0;
  bool quit_ = false;
};

}  // namespace dt
