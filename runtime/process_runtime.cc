#include "runtime/process_runtime.h"

#include <poll.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>

#include <fmt/format.h>

#include "log/log.h"
#include "render/camera.h"
#include "render/png_io.h"
#include "render/renderer.h"
#include "runtime/exercise_ground.h"
#include "runtime/simulated_vehicle_sprite.h"

namespace dt {
namespace {

volatile sig_atomic_t g_stop = 0;
void OnStop(int) { g_stop = 1; }

// The seed of a process's fault decisions: the exercise's, mixed with its address, so processes
// drop different messages.
uint64_t FaultSeed(const ExerciseConfig& exercise, NodeAddress a) {
  return exercise.fault_seed * 0x9E3779B97F4A7C15ull + (uint64_t{a.site} << 16) + a.host;
}

}  // namespace

ProcessTransport StackTransport(std::unique_ptr<Transport> carrier, const FaultConfig& faults,
                                uint64_t fault_seed, const PduBusConfig& bus) {
  ProcessTransport t;
  auto faulty = std::make_unique<FaultyTransport>(std::move(carrier), bus.local, faults, fault_seed,
                                                  DelayUnit::kMilliseconds);
  t.faults = faulty.get();
  auto retrying = std::make_unique<RetryingTransport>(std::move(faulty));
  t.retrying = retrying.get();
  t.transport = std::move(retrying);
  t.bus = std::make_unique<PduBus>(*t.transport, bus);
  return t;
}

ProcessTransport MakeProcessTransport(const ExerciseConfig& exercise,
                                      const ProcessConfig& process) {
  PduBusConfig bus;
  bus.exercise_id = exercise.exercise_id;
  bus.local = process.address;
  bus.terrain_size_x_m = exercise.terrain_size_x_m();
  bus.terrain_size_z_m = exercise.terrain_size_z_m();
  bus.terrain_posts_x = exercise.terrain.posts_x;
  bus.terrain_posts_z = exercise.terrain.posts_z;
  bus.auth.key = exercise.auth.key;
  bus.auth.clock_tolerance = std::chrono::milliseconds(exercise.auth.clock_tolerance_ms);
  // Durable DDS keeps one instance per feature on the feature topics: features go one by one.
  bus.batch = exercise.transport_url.find("durable=1") == std::string::npos;
  // A clock-skew warning names the host by the exercise's name for it, not only its address.
  std::vector<const ProcessConfig*> named = exercise.Processes();
  if (exercise.view) named.push_back(&exercise.view->process);
  if (exercise.dis) named.push_back(&exercise.dis->process);
  for (const ProcessConfig* p : named) bus.auth.sender_names[p->address] = p->name;
  ProcessTransport t = StackTransport(MakeTransport(exercise.transport_url, exercise.exercise_id),
                                      exercise.faults, FaultSeed(exercise, process.address), bus);
  if (const PduAuthenticator* a = t.bus->authenticator()) {
    DT_LOG_INFO(
        "PDUs authenticated with the exercise key {} (incarnation {}, clock tolerance {} ms)",
        exercise.auth.key_file.string(), a->incarnation(), exercise.auth.clock_tolerance_ms);
  } else {
    DT_LOG_WARN(
        "exercise \"{}\" runs WITHOUT PDU authentication ([auth] mode = \"none\" in {}): any "
        "program on {} can create, change or destroy features and replay old PDUs",
        exercise.name, exercise.source.string(), exercise.transport_url);
  }
  return t;
}

ReplicaConfig MakeReplicaConfig(const ExerciseConfig& exercise, const ProcessConfig& process,
                                NodeRole role) {
  ReplicaConfig rc;
  rc.address = process.address;
  rc.role = role;
  rc.max_feature_period_ms = exercise.protocol.max_feature_period_ms;
  rc.silence_ms = exercise.protocol.silence_ms;
  rc.playback_retry_ms = exercise.protocol.playback_retry_ms;
  rc.playback_window = exercise.protocol.playback_window;
  rc.playback_window_max = exercise.protocol.playback_window_max;
  rc.anti_entropy_period_ms = exercise.protocol.anti_entropy_period_ms;
  rc.gap_give_up_ms = exercise.protocol.gap_give_up_ms;
  rc.ground_source = ExerciseGroundSource(exercise);
  if (exercise.server) rc.members[exercise.server->address] = NodeRole::kServer;
  rc.require_server = exercise.require_server();
  if (exercise.standby) rc.members[exercise.standby->address] = NodeRole::kStandby;
  for (const ProcessConfig& n : exercise.nodes) rc.members[n.address] = NodeRole::kNode;
  if (exercise.view) rc.members[exercise.view->process.address] = NodeRole::kObserver;
  // The DIS gateway observes, unless it imports outside craters: then it authors them as a node.
  if (exercise.dis) {
    rc.members[exercise.dis->process.address] =
        exercise.dis->import_craters ? NodeRole::kNode : NodeRole::kObserver;
  }
  return rc;
}

void InstallStopSignals() {
  struct sigaction sa {};
  sa.sa_handler = OnStop;
  sigaction(SIGTERM, &sa, nullptr);
  sigaction(SIGINT, &sa, nullptr);
  signal(SIGPIPE, SIG_IGN);
}

bool StopRequested() { return g_stop != 0; }

void WaitForWork(int transport_fd, bool needs_handling, const ControlServer& control,
                 int timeout_ms) {
  std::vector<pollfd> fds = {{transport_fd, POLLIN, 0}};
  control.AddPollFds(fds);
  poll(fds.data(), fds.size(), needs_handling ? std::min(timeout_ms, 1) : timeout_ms);
}

int64_t MonotonicMs() {
  static const auto start = std::chrono::steady_clock::now();
  return std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::steady_clock::now() -
                                                               start)
      .count();
}

StatusReport MakeStatusReport(const std::string& name, NodeRole role, const Replica& replica,
                              const ProcessTransport& transport,
                              const std::vector<SimulatedVehicle>& vehicles) {
  const Replica::Counters c = replica.counters();
  const RetryingTransport::Counters w = transport.retrying->counters();
  StatusReport r;
  r.name = name;
  r.address = replica.config().address;
  r.role = role;
  r.require_server = replica.config().require_server;
  r.signed_on = replica.signed_on();
  r.caught_up = replica.caught_up();
  r.diverged = replica.diverged();
  r.diverged_since_ms = replica.diverged_since_ms();
  r.features = replica.live_feature_count();
  r.digest = replica.Digest();
  r.own_feature_number = replica.own_feature_number();
  r.own_change_seq = replica.own_change_seq();
  r.acknowledged_change_seq = replica.acknowledged_change_seq();
  r.sent = c.sent;
  r.received = c.received;
  r.rejected = c.rejected;
  r.played_back = c.played_back;
  r.applied = c.applied;
  r.ignored_stale = c.ignored_stale;
  r.fault_dropped = transport.faults->dropped();
  r.drop_probability = transport.faults->faults().config().drop_probability;
  r.write_queued = w.queued;
  r.write_retried = w.retried;
  r.write_failed = w.failed_writes;
  r.write_given_up = w.given_up;
  r.voided = c.voided;
  r.gave_up = c.gave_up;
  r.refused_stranger = c.refused_stranger;
  r.refused_role = c.refused_role;
  r.refused_claim = c.refused_claim;
  r.refused_lamport = c.refused_lamport;
  r.refused_ground = c.refused_ground;
  r.ground_digest = replica.ground_digest().ToHex();
  r.ground_source = replica.config().ground_source;
  r.ground_refused = replica.ground_refused();
  if (auto exercise = replica.exercise_ground_digest())
    r.exercise_ground_digest = exercise->ToHex();
  for (const auto& [member, digest] : replica.ground_mismatches()) {
    r.ground_mismatches.push_back({member, digest.ToHex()});
  }
  // The bus's rejections by reason (validation and authentication), all of them, zeros too.
  const RejectCounters& rejects = transport.bus->rejects();
  for (size_t i = 0; i < kRejectReasonCount; ++i) {
    r.rejected_by_reason[i] = rejects.count(static_cast<RejectReason>(i));
  }
  // Senders whose authenticated PDUs this process tracks for replays (itself included).
  const PduAuthenticator* auth = transport.bus->authenticator();
  r.authenticated = auth != nullptr;
  r.auth_senders = auth != nullptr ? auth->senders_tracked() : 0;
  if (auth != nullptr) {
    const ClockReport clock = auth->clock_report();
    for (const ClockSuspect& suspect : clock.suspects) {
      r.clock_suspects.push_back({suspect.sender, suspect.offset_ms, suspect.stale});
    }
    r.clock_suspect_senders = clock.suspects.size();
    r.clock_worst_offset_ms = clock.worst_offset_ms();
    r.own_clock_suspect = clock.own_offset_ms.has_value();
    r.own_clock_offset_ms = clock.own_offset_ms.value_or(0);
  }
  for (const auto& [origin, max] : replica.max_feature_known()) {
    r.max_features.push_back({origin, max});
  }
  for (const AntiEntropy::Divergence& d : replica.divergences()) {
    r.divergences.push_back({d.author, d.peer, d.first_seq, d.last_seq, d.located, d.since_ms});
  }
  for (size_t i = 0; i < vehicles.size(); ++i) {
    const SimulatedVehicle& v = vehicles[i];
    const VehiclePose p = v.pose();
    StatusReport::Vehicle& out = r.vehicles.emplace_back();
    out.index = i;
    out.type = v.type_name();
    out.x_m = p.x_m;
    out.z_m = p.z_m;
    out.y_m = p.elevation_m;
    out.heading_rad = p.heading_rad;
    out.speed_mps = p.speed_mps;
    if (v.bridge().number != 0) out.on_bridge = v.bridge();
    out.alive = v.alive();
    out.model = v.model();
    out.damage = v.damage();
  }
  return r;
}

std::string StatusText(const std::string& name, NodeRole role, const Replica& replica,
                       const ProcessTransport& transport,
                       const std::vector<SimulatedVehicle>& vehicles) {
  return MakeStatusReport(name, role, replica, transport, vehicles).ToText();
}

Status RenderMapPng(const Terrain& terrain, const std::vector<SimulatedVehicle>& vehicles,
                    const std::string& path) {
  std::vector<VehicleSprite> sprites;
  for (const SimulatedVehicle& v : vehicles) sprites.push_back(SpriteOf(v));
  return RenderMapPng(terrain, sprites, path);
}

Status RenderMapPng(const Terrain& terrain, const std::vector<VehicleSprite>& sprites,
                    const std::string& path) {
  try {
    static Renderer* renderer = new Renderer();  // one OSMesa context for the process's life
    const Camera camera = Camera::MapFitting(
        Rect{0.0, 0.0, terrain.ground().size_x_m(), terrain.ground().size_z_m()}, kMapRenderPx);
    // A vehicle narrower than a pixel can cover no pixel centre and vanish from the map (a
    // 2.4 m truck on a 1280 m terrain's 2.5 m pixels): each is drawn at least two pixels long
    // and wide, so every vehicle shows.
    const double min_side_m = 2.0 * camera.metres_per_pixel();
    std::vector<VehicleSprite> shown = sprites;
    for (VehicleSprite& v : shown) {
      v.length_m = std::max(v.length_m, min_side_m);
      v.width_m = std::max(v.width_m, min_side_m);
    }
    RenderOptions options;
    options.grid_spacing_m = 0.0;
    return WritePng(renderer->Render(terrain, shown, camera, options), path);
  } catch (const std::exception& e) {
    return Error{fmt::format("cannot render {}: {}", path, e.what())};
  }
}

std::optional<ControlReply> AnswerCommonCommand(const ControlCommand& command,
                                                const std::string& name, NodeRole role,
                                                const Replica& replica, ProcessTransport& transport,
                                                const std::vector<SimulatedVehicle>& vehicles) {
  FaultyTransport& faults = *transport.faults;
  switch (command.verb) {
    case ControlVerb::kPing:
      return ControlReply::Ok("pong");
    case ControlVerb::kStatus:
      return ControlReply::Ok(StatusText(name, role, replica, transport, vehicles));
    case ControlVerb::kDigest:
      return ControlReply::Ok(replica.Digest());
    case ControlVerb::kFeatures: {
      std::string body;
      for (const auto& [id, record] : replica.records().all()) {
        if (record.destroyed) continue;
        if (!body.empty()) body += '\n';
        body += id.ToString();
      }
      return ControlReply::Ok(std::move(body));
    }
    case ControlVerb::kRender: {
      if (Status s = RenderMapPng(replica.terrain(), vehicles, command.path); !s) {
        return ControlReply::Fail(s.error().message);
      }
      return ControlReply::Ok(command.path);
    }
    case ControlVerb::kLoss: {
      FaultConfig f = faults.faults().config();
      f.drop_probability = command.drop_probability;
      faults.faults().set_config(f);
      DT_LOG_INFO("receive drop probability now {}", f.drop_probability);
      return ControlReply::Ok();
    }
    case ControlVerb::kPartition:
      faults.faults().Partition({replica.config().address}, command.nodes);
      DT_LOG_INFO("partitioned from {} node(s)", command.nodes.size());
      return ControlReply::Ok();
    case ControlVerb::kHeal:
      faults.faults().Heal();
      DT_LOG_INFO("partitions healed");
      return ControlReply::Ok();
    default:
      return std::nullopt;
  }
}

CatchUpProgress::CatchUpProgress() : tty_(isatty(STDOUT_FILENO) == 1) {}

void CatchUpProgress::Update(int64_t now_ms, const Replica& replica) {
  if (started_ms_ < 0) started_ms_ = now_ms;
  // Short catch-ups show nothing; a terminal line refreshes 4 times a second, logs every 5 s.
  if (now_ms - started_ms_ < 2000) return;
  const int64_t interval_ms = tty_ ? 250 : 5000;
  if (last_ms_ >= 0 && now_ms - last_ms_ < interval_ms) return;
  last_ms_ = now_ms;
  const Replica::Counters c = replica.counters();
  const std::string line =
      fmt::format("catching up: {} features, {} changes applied, {} played back, {:.1f} s",
                  replica.live_feature_count(), c.applied, c.played_back,
                  static_cast<double>(now_ms - started_ms_) / 1000.0);
  if (tty_) {
    std::fprintf(stdout, "\r%s\033[K", line.c_str());
    std::fflush(stdout);
    shown_ = true;
  } else {
    DT_LOG_INFO("{}", line);
  }
}

void CatchUpProgress::Done(int64_t now_ms, const Replica& replica) {
  if (shown_) std::fprintf(stdout, "\n");
  if (started_ms_ >= 0) {
    DT_LOG_INFO("caught up: {} features, {} changes applied in {:.1f} s",
                replica.live_feature_count(), replica.counters().applied,
                static_cast<double>(now_ms - started_ms_) / 1000.0);
  }
  started_ms_ = -1;
  last_ms_ = -1;
  shown_ = false;
}

}  // namespace dt
