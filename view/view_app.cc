#include "view/view_app.h"

#include <chrono>
#include <fstream>
#include <memory>
#include <sstream>
#include <stdexcept>

#include <fmt/format.h>

#include "log/log.h"
#include "runtime/control_client.h"
#include "view/operator_command.h"
#include "view/terrain_window.h"

namespace dt {
namespace {

int64_t WallMs() {
  return std::chrono::duration_cast<std::chrono::milliseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

const ViewConfig& FindView(const ExerciseConfig& exercise, const std::string& name) {
  if (!exercise.view || exercise.view->process.name != name) {
    throw std::invalid_argument(
        fmt::format("{}: no [view] named \"{}\"", exercise.source.string(), name));
  }
  return *exercise.view;
}

}  // namespace

ViewApp::ViewApp(const ExerciseConfig& exercise, const std::string& name, ViewOptions options)
    : ObserverProcess(exercise, FindView(exercise, name).process, NodeRole::kObserver),
      view_(FindView(exercise, name)),
      options_(std::move(options)) {
  MemberNames names;
  std::vector<PolledProcess> polled;
  for (const ProcessConfig* p : exercise.Processes()) {
    names[p->address] = p->name;
    const char* role = exercise.server && p == &*exercise.server     ? "server"
                       : exercise.standby && p == &*exercise.standby ? "standby"
                                                                     : "node";
    if (std::string(role) == "node") nodes_.insert(p->name);
    polled.push_back({p->name, role, p->address.ToString(), exercise.SocketPath(p->name)});
  }
  names[view_.process.address] = view_.process.name;
  // The DIS gateway owns the outside entities it brings in (docs/dis.md "The gateway").
  if (exercise.dis) names[exercise.dis->process.address] = exercise.dis->process.name;
  vehicles_ =
      std::make_unique<SharedVehicleSource>(*transport_.bus, names, exercise.dead_reckoning);
  model_ = std::make_unique<ViewModel>(*replica_, names);
  relief_ = std::make_unique<ReliefTiles>(replica_->terrain().ground());
  poller_ = std::make_unique<ProcessPoller>(polled, options_.poll_period_ms, 1000);
  WebServer::Handlers handlers;
  handlers.snapshot = [this] {
    // Under the publish lock: the copy only (docs/view.md "Messages").
    auto copy = std::make_shared<const SnapshotCopy>(model_->Copy());
    nlohmann::json extra = {{"exercise",
                             {{"name", exercise_.name},
                              {"size_x_m", exercise_.terrain_size_x_m()},
                              {"size_z_m", exercise_.terrain_size_z_m()},
                              {"silence_ms", exercise_.protocol.silence_ms},
                              {"view", view_.process.name},
                              {"commands", options_.allow_commands},
                              {"nodes", nodes_}}},
                            {"relief_tiles", relief_->Describe()}};
    return std::function<std::string()>(
        [copy, extra = std::move(extra)] { return copy->Text(WallMs(), extra); });
  };
  handlers.message = [this](const std::string& text) { return OnMessage(text); };
  handlers.terrain3d = [this](const std::string& query) -> std::pair<int, std::string> {
    // Checked here, built on the loop (the terrain is the loop's): docs/view.md "The 3D view".
    auto r = ParseTerrainWindowQuery(query);
    if (!r) return {400, r.error().message};
    auto json = windows_.Ask(query, kWindowTimeoutMs);
    if (!json) return {503, "the view's loop did not answer in time"};
    return {200, std::move(*json)};
  };
  handlers.relief_tile = [this](const std::string& tile) -> std::pair<int, std::string> {
    auto key = ParseTileKey(tile, relief_->pyramid());
    if (!key) return {404, key.error().message};
    ReliefTiles::Answer a = relief_->Get(key.value(), kTileTimeoutMs);
    if (a.status != 200) return {a.status, std::move(a.why)};
    return {200, *a.png};
  };
  web_ = std::make_unique<WebServer>(view_.http_address, view_.http_port, options_.web_dir,
                                     std::move(handlers));
}

ViewApp::~ViewApp() {
  relief_->Stop();  // a page's thread waiting for a tile would hold the web server's stop
}

std::string ViewApp::url() const {
  return fmt::format("http://{}:{}/", view_.http_address, view_.http_port);
}

void ViewApp::OnTick(int64_t now_ms) {
  std::vector<ProcessRow> rows = poller_->Rows();
  for (ProcessRow& r : rows) {
    const ProcessConfig* p = exercise_.FindProcess(r.name);
    const int64_t heard = replica_->last_heard_ms(p->address);
    r.last_heard_ago_ms = heard < 0 ? -1 : now_ms - heard;
    r.silent = heard < 0 || now_ms - heard > exercise_.protocol.silence_ms;
    // The page shows how long ago in whole tenths of a second: finer would be a delta per tick.
    if (r.last_heard_ago_ms > 0) r.last_heard_ago_ms = r.last_heard_ago_ms / 100 * 100;
  }
  windows_.Serve(
      [this](const std::string& query) {
        return TerrainWindowJson(replica_->terrain(), ParseTerrainWindowQuery(query).value());
      },
      kWindowsPerTick);
  vehicles_->Tick(replica_->terrain(), static_cast<double>(now_ms) / 1000.0);
  const std::vector<VehicleView> vehicles = vehicles_->Vehicles();
  web_->Publish([&] {
    // The JSON delta first (new vehicles' rows name the slots), then the moves in binary.
    std::vector<WebServer::Message> out(2);
    out[1].binary = true;
    // Under the publish lock, as the snapshot's Describe: a page misses no tile's change.
    const nlohmann::json tiles = relief_->Track(replica_->terrain());
    relief_version_ = static_cast<int>(relief_->Version({0, 0, 0}));
    nlohmann::json delta = model_->Update(WallMs(), rows, vehicles, relief_version_, &out[1].data);
    if (!delta.is_null()) out[0].data = delta.dump();
    if (!tiles.is_null()) out.push_back({tiles.dump(), false});
    return out;
  });
  // After the delta: the outlines reach the pages without waiting for the tiles (drawn with
  // OSMesa, on the CPU, on the tiles' own thread).
  relief_->Serve(replica_->terrain(), kTilesPerTick);
}

std::string ViewApp::OnMessage(const std::string& text) {
  nlohmann::json reply = {{"type", "reply"}};
  nlohmann::json m = nlohmann::json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (m.is_object() && m.contains("req")) reply["req"] = m["req"];
  if (!options_.allow_commands) {
    reply["ok"] = false;
    reply["text"] = "operator commands are off: start dt_view with --allow-commands";
    return reply.dump();
  }
  auto c = ParseOperatorCommand(m, nodes_);
  if (!c) {
    reply["ok"] = false;
    reply["text"] = c.error().message;
    return reply.dump();
  }
  DT_LOG_INFO("operator: {} on {}", c.value().line, c.value().node);
  auto r = CallControl(exercise_.SocketPath(c.value().node), c.value().line, 3000);
  if (!r) {
    reply["ok"] = false;
    reply["text"] = r.error().message;
  } else {
    reply["ok"] = r.value().ok;
    reply["text"] = r.value().ok ? r.value().body : r.value().error;
  }
  reply["node"] = c.value().node;
  reply["line"] = c.value().line;
  return reply.dump();
}

std::string ViewApp::RefusalText() const {
  return "the view is an observer and runs no feature commands (send them to a node)";
}

std::string ViewApp::StopSummary() const {
  return fmt::format("{} features, digest {}", replica_->live_feature_count(), replica_->Digest());
}

}  // namespace dt
