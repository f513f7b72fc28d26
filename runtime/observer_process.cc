#include "runtime/observer_process.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <stdexcept>

#include <fmt/format.h>

#include "log/log.h"
#include "runtime/exercise_ground.h"

namespace dt {
namespace {

// The run directory holds the control socket and a node member's reservation file: made before
// either.
const ExerciseConfig& WithRunDir(const ExerciseConfig& exercise) {
  std::filesystem::create_directories(exercise.run_dir);
  return exercise;
}

}  // namespace

ObserverProcess::ObserverProcess(const ExerciseConfig& exercise, const ProcessConfig& process,
                                 NodeRole role)
    : exercise_(WithRunDir(exercise)),
      process_(process),
      role_(role),
      transport_(MakeProcessTransport(exercise, process)) {
  ReplicaConfig rc = MakeReplicaConfig(exercise, process, role);
  if (role == NodeRole::kNode) {
    ids_ = std::make_unique<IdReservationFile>(exercise.run_dir / (process.name + ".ids"),
                                               process.address);
    rc.ids = ids_.get();
  }
  replica_ =
      std::make_unique<Replica>(std::move(rc), BuildExerciseGround(exercise), *transport_.bus);
  if (!replica_->load_status()) throw std::runtime_error(replica_->load_status().error().message);
}

ObserverProcess::~ObserverProcess() = default;

void ObserverProcess::Start(int64_t now_ms) {
  now_ms_ = now_ms;
  replica_->SignOn(now_ms);
  OnStart(now_ms);
}

void ObserverProcess::Tick(int64_t now_ms) {
  PduBus::Batch batch(*transport_.bus);  // the tick's PDUs leave packed, at its end
  now_ms_ = now_ms;
  replica_->Tick(now_ms);
  OnTick(now_ms);
}

void ObserverProcess::Wait(const ControlServer& control, int timeout_ms) {
  std::vector<pollfd> fds = {{transport_.bus->Fd(), POLLIN, 0}};
  AddPollFds(fds);
  control.AddPollFds(fds);
  // Held (delayed) messages and queued writes need HandleTimeout calls even while the bus is
  // quiet.
  ::poll(fds.data(), fds.size(),
         transport_.needs_handling() ? std::min(timeout_ms, 1) : timeout_ms);
  now_ms_ = MonotonicMs();
  if (Result<int> r = transport_.bus->HandleTimeout(0); !r && !StopRequested()) {
    DT_LOG_WARN("receive: {}", r.error().message);
  }
  OnWoken(now_ms_);
}

ControlReply ObserverProcess::Handle(std::string_view line) {
  static const std::vector<SimulatedVehicle> kNoVehicles;  // it drives none
  Result<ControlCommand> c = ParseControlCommand(line);
  if (!c) return ControlReply::Fail(c.error().message);
  if (c.value().verb == ControlVerb::kQuit) {
    quit_ = true;
    return ControlReply::Ok("bye");
  }
  if (std::optional<ControlReply> r = HandleOwn(c.value())) return *r;
  if (std::optional<ControlReply> r = AnswerCommonCommand(c.value(), process_.name, role_,
                                                          *replica_, transport_, kNoVehicles)) {
    if (c.value().verb == ControlVerb::kStatus && r->ok) {
      if (const std::string own = StatusLines(); !own.empty()) r->body += "\n" + own;
    }
    return *r;
  }
  return ControlReply::Fail(fmt::format("\"{}\": {}", line, RefusalText()));
}

void ObserverProcess::Run() {
  InstallStopSignals();
  ControlServer control(exercise_.SocketPath(process_.name),
                        [this](std::string_view line) { return Handle(line); });
  const int64_t tick_ms = 1000 / exercise_.tick_hz;
  int64_t next_ms = MonotonicMs();
  Start(next_ms);
  const std::string ready = ReadyLines();
  std::printf("%s%sREADY %s\n", ready.c_str(), ready.empty() ? "" : "\n", process_.name.c_str());
  std::fflush(stdout);
  const auto running = [this] { return !StopRequested() && !quit_; };
  while (running()) {
    Tick(MonotonicMs());
    control.Poll(0);
    next_ms += tick_ms;
    // A tick that overran by more than a tick starts the schedule again rather than racing.
    if (next_ms < MonotonicMs() - tick_ms) next_ms = MonotonicMs();
    for (int64_t left; (left = next_ms - MonotonicMs()) > 0 && running();) {
      Wait(control, static_cast<int>(left));
      control.Poll(0);
    }
    Wait(control, 0);  // a tick that overran still hears the bus and the process's descriptors
  }
  DT_LOG_INFO("stopping: {}", StopSummary());
}

}  // namespace dt
