// dt_server: the dynamic terrain server (or, with --standby, its standby): a durable replica in
// SQLite under the exercise's run_dir, served by a fixed-rate loop with a control socket.
#include <cstdio>
#include <filesystem>
#include <optional>

#include <fmt/format.h>
#include <CLI/CLI.hpp>

#include "log/log.h"
#include "runtime/control_server.h"
#include "runtime/exercise_flags.h"
#include "runtime/exercise_ground.h"
#include "runtime/process_runtime.h"
#include "server/server_replica.h"

namespace {

dt::ControlReply Handle(std::string_view line, const std::string& name, dt::NodeRole role,
                        dt::ServerReplica& server, dt::ProcessTransport& transport, bool& quit) {
  static const std::vector<dt::SimulatedVehicle> kNoVehicles;  // a server drives none
  dt::Result<dt::ControlCommand> c = dt::ParseControlCommand(line);
  if (!c) return dt::ControlReply::Fail(c.error().message);
  switch (c.value().verb) {
    case dt::ControlVerb::kQuit:
      quit = true;
      return dt::ControlReply::Ok("bye");
    // Both refuse, with a reply naming the path and the reason, anything but a regular file of
    // bounded size, and neither can block the loop (base/regular_file.h).
    case dt::ControlVerb::kExport:
      if (dt::Status s = server.ExportTerrain(c.value().path); !s) {
        DT_LOG_WARN("export refused: {}", s.error().message);
        return dt::ControlReply::Fail(s.error().message);
      }
      DT_LOG_INFO("exported the terrain to {}", c.value().path);
      return dt::ControlReply::Ok(c.value().path);
    case dt::ControlVerb::kImport:
      if (dt::Status s = server.ImportTerrain(c.value().path); !s) {
        DT_LOG_WARN("import refused: {}", s.error().message);
        return dt::ControlReply::Fail(s.error().message);
      }
      DT_LOG_INFO("imported {}", c.value().path);
      return dt::ControlReply::Ok(c.value().path);
    default:
      break;
  }
  if (auto r = dt::AnswerCommonCommand(c.value(), name, role, server.replica(), transport,
                                       kNoVehicles)) {
    return *r;
  }
  return dt::ControlReply::Fail(fmt::format(
      "\"{}\": the server holds the terrain but takes feature commands from nodes only", line));
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"The dynterrain dynamic terrain server"};
  dt::ExerciseFlags flags;
  std::string name = "server";
  std::string level = "info";
  bool standby = false;
  flags.AddTo(app);
  app.add_option("--name", name, "the server's name in the exercise")->capture_default_str();
  app.add_flag("--standby", standby, "run as the standby ([standby] of the exercise)");
  app.add_option("--log-level", level, "debug, info, warn or error")->capture_default_str();
  CLI11_PARSE(app, argc, argv);

  try {
    dt::log::Init(name, level);
    dt::ExerciseConfig exercise = flags.Load();
    const std::optional<dt::ProcessConfig>& entry = standby ? exercise.standby : exercise.server;
    const dt::ProcessConfig* process = entry ? &*entry : nullptr;
    if (process == nullptr || process->name != name) {
      throw std::invalid_argument(fmt::format("{}: no {} named \"{}\"", exercise.source.string(),
                                              standby ? "[standby]" : "[server]", name));
    }
    const dt::NodeRole role = standby ? dt::NodeRole::kStandby : dt::NodeRole::kServer;
    dt::InstallStopSignals();
    std::filesystem::create_directories(exercise.run_dir);
    dt::ProcessTransport transport = dt::MakeProcessTransport(exercise, *process);
    const dt::ReplicaConfig rc = dt::MakeReplicaConfig(exercise, *process, role);
    const std::filesystem::path db = exercise.run_dir / (name + ".db");
    const int64_t t0 = dt::MonotonicMs();
    auto opened = dt::ServerReplica::Open(rc, dt::MakeExerciseGround(exercise), *transport.bus, db);
    // A database refused as a whole (not ours, damaged, a row that fails its checks) ends the
    // start here with exit 2 and the message naming the file and the row.
    if (!opened) throw std::runtime_error(opened.error().message);
    dt::ServerReplica& server = *opened.value();
    DT_LOG_INFO("{} opened with {} features in {} ms", db.string(),
                server.replica().live_feature_count(), dt::MonotonicMs() - t0);
    bool quit = false;
    dt::ControlServer control(exercise.SocketPath(name), [&](std::string_view line) {
      return Handle(line, name, role, server, transport, quit);
    });

    const int64_t tick_ms = 1000 / exercise.tick_hz;
    int64_t next_ms = dt::MonotonicMs();
    server.replica().SignOn(next_ms);
    bool ready = false;
    while (!dt::StopRequested() && !quit) {
      server.replica().Tick(dt::MonotonicMs());
      if (!server.replica().store_status()) {
        DT_LOG_ERROR("store: {}", server.replica().store_status().error().message);
      }
      if (!ready && server.replica().signed_on()) {
        ready = true;
        std::printf("READY %s\n", name.c_str());
        std::fflush(stdout);
      }
      control.Poll(0);
      next_ms += tick_ms;
      if (next_ms < dt::MonotonicMs() - tick_ms) next_ms = dt::MonotonicMs();
      for (int64_t left;
           (left = next_ms - dt::MonotonicMs()) > 0 && !dt::StopRequested() && !quit;) {
        dt::WaitForWork(transport.bus->Fd(), transport.needs_handling(), control,
                        static_cast<int>(left));
        (void)transport.bus->HandleTimeout(0);
        control.Poll(0);
      }
      (void)transport.bus->HandleTimeout(0);  // at least once per tick, even when behind
    }
    if (dt::Status s = server.Flush(); !s) {
      DT_LOG_ERROR("final save failed: {}", s.error().message);
      return 1;
    }
    DT_LOG_INFO("saved and stopping: {} features, digest {}", server.replica().live_feature_count(),
                server.replica().Digest());
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "dt_server %s: %s\n", name.c_str(), e.what());
    return 2;
  }
}
