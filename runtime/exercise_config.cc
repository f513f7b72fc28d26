#include "runtime/exercise_config.h"

#include <arpa/inet.h>

#include <fstream>
#include <limits>
#include <numbers>
#include <set>
#include <sstream>
#include <stdexcept>
#include <tuple>

#include <fmt/format.h>

#include "pdu/pdu_type.h"
#include "runtime/toml_reader.h"
#include "terrain/height_grid.h"
#include "terrain/terrain_file.h"
#include "transport/transport.h"
#include "vehicle/shipped_friction.h"
#include "vehicle/vehicle_type.h"

namespace dt {
namespace {

constexpr double kDegToRad = std::numbers::pi / 180.0;

// The keys of the process tables (docs/node.md "Exercise files").
const std::vector<std::string> kServerKeys = {"name", "site", "host"};
const std::vector<std::string> kNodeKeys = {"name", "site", "host", "scenario", "vehicle", "group"};
const std::vector<std::string> kGroupKeys = {"type", "count", "area", "seed", "model"};
const std::vector<std::string> kAreaKeys = {"x_min_m", "x_max_m", "z_min_m", "z_max_m"};

VehicleConfig ReadVehicle(const TomlReader& r) {
  VehicleConfig v;
  v.type = r.String("type", "tank");
  if (!BuiltInVehicleType(v.type)) r.Fail("type", "unknown vehicle type (tank, truck, jeep)");
  v.x_m = r.Double("x_m", 0.0, 1e9);
  v.z_m = r.Double("z_m", 0.0, 1e9);
  v.heading_rad = r.Double("heading_deg", 0.0, -360.0, 360.0) * kDegToRad;
  const std::string model = r.String("model", "physical");
  const std::optional<VehicleModel> m = ParseVehicleModel(model);
  if (!m) r.Fail("model", "expected \"physical\" or \"light\"");
  v.model = *m;
  r.Finish();
  return v;
}

// "320 m" for a square terrain, "320 x 160 m" for another.
std::string TerrainSizeText(double size_x_m, double size_z_m) {
  return size_x_m == size_z_m ? fmt::format("{} m", size_x_m)
                              : fmt::format("{} x {} m", size_x_m, size_z_m);
}

VehicleGroupConfig ReadGroup(const TomlReader& r, double size_x_m, double size_z_m) {
  VehicleGroupConfig g;
  g.type = r.String("type", "truck");
  if (!BuiltInVehicleType(g.type)) r.Fail("type", "unknown vehicle type (tank, truck, jeep)");
  g.count = static_cast<int>(r.Int("count", 1, kMaxGroupVehicles));
  g.seed = static_cast<uint64_t>(r.Int("seed", 1, 0, INT64_MAX));
  const std::string model = r.String("model", "physical");
  const std::optional<VehicleModel> m = ParseVehicleModel(model);
  if (!m) r.Fail("model", "expected \"physical\" or \"light\"");
  g.model = *m;
  g.area = {0.0, size_x_m, 0.0, size_z_m};
  if (auto a = r.OptionalTable("area", kAreaKeys)) {
    g.area.x_min_m = a->Double("x_min_m", 0.0, 0.0, size_x_m);
    g.area.x_max_m = a->Double("x_max_m", size_x_m, 0.0, size_x_m);
    g.area.z_min_m = a->Double("z_min_m", 0.0, 0.0, size_z_m);
    g.area.z_max_m = a->Double("z_max_m", size_z_m, 0.0, size_z_m);
    const double length_m = BuiltInVehicleType(g.type).value().length_m;
    if (g.area.x_max_m - g.area.x_min_m < 2 * length_m) {
      a->Fail("x_max_m", fmt::format("the area must be at least {} m wide (x_min_m = {})",
                                     2 * length_m, g.area.x_min_m));
    }
    if (g.area.z_max_m - g.area.z_min_m < 2 * length_m) {
      a->Fail("z_max_m", fmt::format("the area must be at least {} m deep (z_min_m = {})",
                                     2 * length_m, g.area.z_min_m));
    }
    a->Finish();
  }
  r.Finish();
  return g;
}

// [terrain] ground_file, after the grid keys were read with their defaults: the saved terrain's
// header is read here for the grid's shape, so a missing or foreign file stops every process at
// once; its ground is read where it is built (BuildExerciseGround, docs/node.md "Starting from a
// saved terrain").
void ReadGroundFile(const TomlReader& t, const std::filesystem::path& base_dir,
                    GroundReading reading, ExerciseConfig& c) {
  for (const char* key :
       {"posts_per_side", "posts_x", "posts_z", "spacing_m", "relief_m", "seed"}) {
    if (t.Has(key)) {
      t.Fail(key, "the ground_file sets the ground: give no grid or random-ground keys with it");
    }
  }
  const std::string file = t.String("ground_file");
  if (file.empty()) t.Fail("ground_file", "must name a terrain file");
  const std::filesystem::path base =
      base_dir.empty() ? std::filesystem::current_path() : std::filesystem::absolute(base_dir);
  c.ground_file = std::filesystem::absolute(base / file).lexically_normal();
  if (t.Has("ground_cache_dir")) {
    const std::string dir = t.String("ground_cache_dir");
    if (dir.empty()) t.Fail("ground_cache_dir", "must name a directory");
    c.ground_file_cache_dir = std::filesystem::absolute(base / dir).lexically_normal();
  }
  if (reading == GroundReading::kSkip) return;
  Result<TerrainFileShape> shape = ProbeTerrainFile(c.ground_file);
  if (!shape) {
    t.Fail("ground_file", fmt::format("{}: {}", c.ground_file.string(), shape.error().message));
  }
  c.terrain.posts_x = shape.value().posts_x;
  c.terrain.posts_z = shape.value().posts_z;
  c.terrain.spacing_m = shape.value().spacing_m;
  c.ground_file_shape = shape.value();
}

ProcessConfig ReadProcess(const TomlReader& r, const std::filesystem::path& base_dir, bool is_node,
                          double size_x_m, double size_z_m) {
  ProcessConfig p;
  p.name = r.String("name");
  if (p.name.empty() || p.name.find_first_of("/ \t") != std::string::npos) {
    r.Fail("name", "must be non-empty with no '/' or spaces");
  }
  p.address.site = static_cast<uint16_t>(r.Int("site", 1, 65535));
  p.address.host = static_cast<uint16_t>(r.Int("host", 1, 65535));
  if (is_node) {
    const std::string scenario = r.String("scenario", "");
    if (!scenario.empty()) p.scenario = std::filesystem::absolute(base_dir / scenario);
    for (const TomlReader& v :
         r.TableArray("vehicle", {"type", "x_m", "z_m", "heading_deg", "model"})) {
      VehicleConfig vc = ReadVehicle(v);
      if (vc.x_m > size_x_m || vc.z_m > size_z_m) {
        v.Fail(vc.x_m > size_x_m ? "x_m" : "z_m",
               fmt::format("vehicle at ({}, {}) is off the {} terrain", vc.x_m, vc.z_m,
                           TerrainSizeText(size_x_m, size_z_m)));
      }
      p.vehicles.push_back(vc);
    }
    for (const TomlReader& g : r.TableArray("group", kGroupKeys)) {
      p.groups.push_back(ReadGroup(g, size_x_m, size_z_m));
    }
    if (p.start_vehicle_count() > kMaxNodeVehicles) {
      r.FailTable(fmt::format("[[node.vehicle]] and [[node.group]] hold {} vehicles, more than {}",
                              p.start_vehicle_count(), kMaxNodeVehicles));
    }
  }
  r.Finish();
  return p;
}

AuthSettings ReadAuth(const TomlReader& top, const std::filesystem::path& base_dir) {
  const std::optional<TomlReader> a =
      top.OptionalTable("auth", {"mode", "key_file", "clock_tolerance_ms"});
  if (!a) {
    top.Fail("auth",
             "missing: name the exercise key with [auth] key_file = \"<file>\" (make one: head -c "
             "32 /dev/urandom > <file>), or run without authentication with [auth] mode = "
             "\"none\"");
  }
  AuthSettings auth;
  const std::string mode = a->String("mode", "key");
  if (mode != "key" && mode != "none") a->Fail("mode", "expected \"key\" or \"none\"");
  auth.keyless = mode == "none";
  if (auth.keyless) {
    if (a->Has("key_file")) a->Fail("key_file", "mode = \"none\" runs without a key: remove it");
  } else {
    const std::string file = a->String("key_file");
    if (file.empty()) a->Fail("key_file", "must name a file");
    auth.key_file = std::filesystem::absolute(base_dir / file).lexically_normal();
    try {
      auth.key = ExerciseKey::FromFile(auth.key_file);
    } catch (const std::invalid_argument& e) {
      a->Fail("key_file", e.what());
    }
  }
  auth.clock_tolerance_ms = static_cast<int>(a->Int("clock_tolerance_ms", 30000, 100, 3600000));
  a->Finish();
  return auth;
}

bool KnownTransport(std::string_view url) {
  return url.rfind("udpm://", 0) == 0 || url.rfind("dds://", 0) == 0 ||
         url.rfind("memq://", 0) == 0;
}

uint32_t Ipv4(const TomlReader& r, std::string_view key, const std::string& text) {
  in_addr a{};
  if (inet_pton(AF_INET, text.c_str(), &a) != 1) r.Fail(key, "expected a dotted IPv4 address");
  return ntohl(a.s_addr);
}

DisConfig ReadDis(const TomlReader& r, const std::filesystem::path& base) {
  DisConfig d;
  d.bind_address = r.String("bind_address", d.bind_address);
  (void)Ipv4(r, "bind_address", d.bind_address);
  d.udp_port = static_cast<int>(r.Int("udp_port", 3000, 1, 65535));
  d.destination = r.String("destination", d.destination);
  const uint32_t dest = Ipv4(r, "destination", d.destination);
  if (dest == 0) r.Fail("destination", "0.0.0.0 is no destination");
  d.interface_address = r.String("interface_address", d.interface_address);
  (void)Ipv4(r, "interface_address", d.interface_address);
  d.multicast_ttl = static_cast<int>(r.Int("multicast_ttl", 1, 0, 255));
  d.dis_exercise_id = static_cast<uint8_t>(r.Int("dis_exercise_id", 1, 1, 255));
  d.import_craters = r.Bool("import_craters", false);
  d.latitude_deg = r.Double("latitude_deg", 0.0, -90.0, 90.0);
  d.longitude_deg = r.Double("longitude_deg", 0.0, -180.0, 180.0);
  d.height_m = r.Double("height_m", 0.0, -12000.0, 100000.0);
  d.feature_period_ms = static_cast<int>(r.Int("feature_period_ms", 5000, 100, 3600000));
  // At most a UDP datagram's payload over IPv4; at least a few Entity States, or bundling is moot.
  d.bundle_max_bytes = static_cast<int>(r.Int("bundle_max_bytes", 0, 0, 65507));
  if (d.bundle_max_bytes != 0 && d.bundle_max_bytes < 576) {
    r.Fail("bundle_max_bytes",
           fmt::format("{} bytes: 0 (off) or 576 to 65507", d.bundle_max_bytes));
  }
  d.process = ReadProcess(r, base, false, 0.0, 0.0);
  return d;
}

}  // namespace

bool DisConfig::multicast() const {
  in_addr a{};
  return inet_pton(AF_INET, destination.c_str(), &a) == 1 && (ntohl(a.s_addr) >> 28) == 0xE;
}

void ApplyOverrides(ExerciseConfig& exercise, const std::string& transport_url,
                    const std::string& run_dir) {
  if (!transport_url.empty()) {
    if (!KnownTransport(transport_url)) {
      throw std::invalid_argument(fmt::format(
          "--transport \"{}\": expected a udpm://, dds:// or memq:// URL", transport_url));
    }
    exercise.transport_url = transport_url;
  }
  if (!run_dir.empty()) exercise.run_dir = std::filesystem::absolute(run_dir);
}

int ProcessConfig::start_vehicle_count() const {
  int n = static_cast<int>(vehicles.size());
  for (const VehicleGroupConfig& g : groups) n += g.count;
  return n;
}

std::vector<const ProcessConfig*> ExerciseConfig::Processes() const {
  std::vector<const ProcessConfig*> out;
  if (server) out.push_back(&*server);
  if (standby) out.push_back(&*standby);
  for (const ProcessConfig& n : nodes) out.push_back(&n);
  return out;
}

const ProcessConfig* ExerciseConfig::FindProcess(std::string_view process_name) const {
  for (const ProcessConfig* p : Processes()) {
    if (p->name == process_name) return p;
  }
  if (view && view->process.name == process_name) return &view->process;
  if (dis && dis->process.name == process_name) return &dis->process;
  return nullptr;
}

std::filesystem::path ExerciseConfig::SocketPath(std::string_view process_name) const {
  return run_dir / (std::string(process_name) + ".sock");
}

std::optional<HostsMode> ParseHostsMode(std::string_view text) {
  if (text == "none") return HostsMode::kNone;
  if (text == "lan") return HostsMode::kLan;
  if (text == "wan") return HostsMode::kWan;
  return std::nullopt;
}

std::string_view HostsModeName(HostsMode mode) {
  switch (mode) {
    case HostsMode::kNone:
      return "none";
    case HostsMode::kLan:
      return "lan";
    case HostsMode::kWan:
      return "wan";
  }
  return "none";
}

ExerciseConfig ParseExerciseConfig(std::string_view toml_text, std::string_view source_name,
                                   const std::filesystem::path& base_dir, GroundReading ground) {
  const toml::table root = TomlReader::ParseText(toml_text, source_name);
  const TomlReader top(root, std::string(source_name), "",
                       {"exercise", "terrain", "protocol", "faults", "server", "standby", "node",
                        "auth", "view", "dis", "vehicles", "hosts"});
  ExerciseConfig c;
  c.source = std::string(source_name);

  const TomlReader ex =
      top.Table("exercise", {"name", "id", "transport", "run_dir", "tick_hz", "friction_file"});
  c.name = ex.String("name");
  c.exercise_id = static_cast<uint8_t>(ex.Int("id", 1, 0, 255));
  c.transport_url = ex.String("transport", std::string(kDefaultTransportUrl));
  if (!KnownTransport(c.transport_url)) {
    ex.Fail("transport", "expected a udpm://, dds:// or memq:// URL");
  }
  c.run_dir = std::filesystem::absolute(ex.String("run_dir", "run/" + c.name));
  c.tick_hz = static_cast<int>(ex.Int("tick_hz", 30, 1, 1000));
  // Read below, once base_dir is known.
  const std::string friction_file = ex.String("friction_file", "");
  ex.Finish();

  std::vector<std::string> terrain_keys = {"posts_per_side", "posts_x", "posts_z",    "spacing_m",
                                           "relief_m",       "seed",    "ground_file"};
  terrain_keys.insert(terrain_keys.end(), kElevationKeys.begin(), kElevationKeys.end());
  const TomlReader t = top.Table("terrain", terrain_keys);
  if (t.Has("elevation_file") && t.Has("ground_file")) {
    t.Fail("ground_file",
           "give ground_file (a saved terrain) or elevation_file (a raster), not both");
  }
  if (t.Has("elevation_file")) {
    // The file gives the ground: its posts and spacing (docs/real-ground.md), set below.
    for (const char* key : {"posts_per_side", "posts_x", "posts_z", "relief_m", "seed"}) {
      if (t.Has(key)) t.Fail(key, "elevation_file gives the ground: remove it");
    }
    c.elevation = ReadElevationTerrain(
        t, base_dir.empty() ? std::filesystem::current_path() : std::filesystem::absolute(base_dir),
        ground == GroundReading::kRead);
  } else {
    for (const std::string& key : kElevationKeys) {
      if (key == "elevation_file" || !t.Has(key)) continue;
      if (key == "ground_cache_dir" && t.Has("ground_file")) continue;  // read with it
      t.Fail(key, key == "ground_cache_dir" ? "only with elevation_file or ground_file"
                                            : "only with elevation_file");
    }
  }
  c.ground_read = ground == GroundReading::kRead;
  // A square (posts_per_side, the default) or a rectangle (posts_x and posts_z, both given).
  const bool rectangle = t.Has("posts_x") || t.Has("posts_z");
  if (rectangle) {
    if (t.Has("posts_per_side")) {
      t.Fail("posts_per_side",
             "give either posts_per_side (a square grid) or posts_x and posts_z, not both");
    }
    for (const auto& [key, other] :
         {std::pair{"posts_x", "posts_z"}, std::pair{"posts_z", "posts_x"}}) {
      if (!t.Has(other)) {
        t.Fail(key, fmt::format("{} needs {} too: a rectangular grid gives both", key, other));
      }
    }
    c.terrain.posts_x = static_cast<int>(t.Int("posts_x", 2, kMaxPostsPerSide));
    c.terrain.posts_z = static_cast<int>(t.Int("posts_z", 2, kMaxPostsPerSide));
  } else {
    c.terrain.posts_x = c.terrain.posts_z =
        static_cast<int>(t.Int("posts_per_side", 129, 2, kMaxPostsPerSide));
  }
  c.terrain.spacing_m = t.Double("spacing_m", 10.0, 0.01, 10000.0);
  c.terrain.relief_m = t.Double("relief_m", 50.0, 0.0, 10000.0);
  c.terrain.seed = static_cast<uint64_t>(t.Int("seed", 1, 0, INT64_MAX));
  if (t.Has("ground_file")) ReadGroundFile(t, base_dir, ground, c);
  if (c.elevation && c.ground_read) {
    c.terrain.posts_x = c.elevation->layout.posts_x;
    c.terrain.posts_z = c.elevation->layout.posts_z;
    c.terrain.spacing_m = c.elevation->layout.spacing_m;
  }
  t.Finish();

  bool require_server = true;
  if (auto p =
          top.OptionalTable("protocol", {"max_feature_period_ms", "silence_ms", "playback_retry_ms",
                                         "playback_window", "playback_window_max", "require_server",
                                         "anti_entropy_period_ms", "gap_give_up_ms"})) {
    require_server = p->Bool("require_server", true);
    c.protocol.max_feature_period_ms =
        static_cast<int>(p->Int("max_feature_period_ms", 500, 10, 600000));
    c.protocol.silence_ms = static_cast<int>(p->Int("silence_ms", 2000, 10, 3600000));
    c.protocol.playback_retry_ms = static_cast<int>(p->Int("playback_retry_ms", 500, 10, 600000));
    c.protocol.playback_window = static_cast<int>(p->Int("playback_window", 256, 1, 1000000));
    c.protocol.playback_window_max =
        static_cast<int>(p->Int("playback_window_max", 8192, 1, kMaxPlaybackSpan));
    c.protocol.anti_entropy_period_ms =
        static_cast<int>(p->Int("anti_entropy_period_ms", 1000, 0, 600000));
    c.protocol.gap_give_up_ms = static_cast<int>(
        p->Int("gap_give_up_ms", 15 * int64_t{c.protocol.silence_ms}, 0, 86400000));
    if (c.protocol.gap_give_up_ms != 0 && c.protocol.gap_give_up_ms <= 2 * c.protocol.silence_ms) {
      p->Fail("gap_give_up_ms", fmt::format("must be 0 (never) or exceed 2 x silence_ms ({})",
                                            2 * c.protocol.silence_ms));
    }
    if (c.protocol.silence_ms <= c.protocol.max_feature_period_ms) {
      p->Fail("silence_ms", fmt::format("must exceed max_feature_period_ms ({})",
                                        c.protocol.max_feature_period_ms));
    }
    p->Finish();
  }

  // A file named without a folder ("ex.toml") has an empty parent: the current directory.
  const std::filesystem::path base =
      base_dir.empty() ? std::filesystem::current_path() : std::filesystem::absolute(base_dir);
  c.auth = ReadAuth(top, base);
  if (friction_file.empty()) {
    c.friction =
        std::shared_ptr<const FrictionTable>(&ShippedFrictionTable(), [](const FrictionTable*) {});
  } else {
    c.friction_file = std::filesystem::absolute(base / friction_file).lexically_normal();
    try {
      c.friction = std::make_shared<const FrictionTable>(FrictionTable::LoadFile(c.friction_file));
    } catch (const std::invalid_argument& e) {
      ex.Fail("friction_file", e.what());
    }
  }

  if (auto f = top.OptionalTable(
          "faults",
          {"drop_probability", "duplicate_probability", "reorder_probability", "reorder_window",
           "seed", "delay_ms", "jitter_ms", "other_site_delay_ms", "other_site_jitter_ms"})) {
    c.faults.drop_probability = f->Double("drop_probability", 0.0, 0.0, 1.0);
    c.faults.duplicate_probability = f->Double("duplicate_probability", 0.0, 0.0, 1.0);
    c.faults.reorder_probability = f->Double("reorder_probability", 0.0, 0.0, 1.0);
    // Every delay of a process's FaultyTransport counts milliseconds (runtime/process_runtime.h).
    c.faults.reorder_window = f->Int("reorder_window", 0, 0, 60000);
    // Each received copy waits delay_ms +- jitter_ms; one from another site (a WAN) waits
    // other_site_delay_ms +- other_site_jitter_ms more.
    for (auto [delay_key, jitter_key, min, max] :
         {std::tuple{"delay_ms", "jitter_ms", &c.faults.min_delay, &c.faults.max_delay},
          std::tuple{"other_site_delay_ms", "other_site_jitter_ms", &c.faults.other_site_min_delay,
                     &c.faults.other_site_max_delay}}) {
      const int64_t delay = f->Int(delay_key, 0, 0, 60000);
      const int64_t jitter = f->Int(jitter_key, 0, 0, 60000);
      if (jitter > delay) {
        f->Fail(jitter_key, fmt::format("{} exceeds {} = {}: a delay never goes below 0", jitter,
                                        delay_key, delay));
      }
      std::tie(*min, *max) = DelayRange(delay, jitter);
    }
    c.fault_seed = static_cast<uint64_t>(f->Int("seed", 1, 0, INT64_MAX));
    f->Finish();
  }

  if (auto h = top.OptionalTable("hosts", {"mode", "rate_mbit", "queue_ms"})) {
    const std::string mode = h->String("mode", "none");
    const std::optional<HostsMode> m = ParseHostsMode(mode);
    if (!m) h->Fail("mode", fmt::format("\"{}\": expected none, lan or wan", mode));
    c.hosts.mode = *m;
    c.hosts.rate_mbit = h->Double("rate_mbit", c.hosts.rate_mbit, 0.1, 100000.0);
    c.hosts.queue_ms = static_cast<int>(h->Int("queue_ms", c.hosts.queue_ms, 1, 10000));
    h->Finish();
  }

  if (auto v =
          top.OptionalTable("vehicles", {"position_threshold_m", "orientation_threshold_deg",
                                         "heartbeat_s", "timeout_heartbeats", "dead_reckoning"})) {
    DeadReckoningThresholds& d = c.dead_reckoning;
    d.position_m = v->Double("position_threshold_m", 1.0, 0.01, 1000.0);
    d.orientation_deg = v->Double("orientation_threshold_deg", 3.0, 0.01, 180.0);
    d.heartbeat_s = v->Double("heartbeat_s", 5.0, 0.1, 3600.0);
    d.timeout_heartbeats = v->Double("timeout_heartbeats", 2.4, 1.0, 100.0);
    const std::string drm = v->String("dead_reckoning", "rvw");
    const auto algorithm = ParseDeadReckoningAlgorithm(drm);
    if (!algorithm) v->Fail("dead_reckoning", "expected static, fpw, rpw, rvw or fvw");
    d.algorithm = *algorithm;
    v->Finish();
  }

  // Where vehicles may stand: anywhere when the ground was not read (its shape is unknown).
  const double size_x_m =
      c.ground_read ? c.terrain_size_x_m() : std::numeric_limits<double>::infinity();
  const double size_z_m =
      c.ground_read ? c.terrain_size_z_m() : std::numeric_limits<double>::infinity();
  if (require_server) {
    top.FailOnUnknownKeys();  // a mistyped [srever] is named, not "server: missing"
    if (!top.Has("server")) {
      top.Fail("server",
               "missing: an exercise needs a [server], or [protocol] "
               "require_server = false for one without");
    }
    c.server = ReadProcess(top.Table("server", kServerKeys), base, false, size_x_m, size_z_m);
    if (auto s = top.OptionalTable("standby", kServerKeys)) {
      c.standby = ReadProcess(*s, base, false, 0.0, 0.0);
    }
  } else {
    for (const char* table : {"server", "standby"}) {
      if (top.Has(table)) {
        // Not Fail(): it would print the whole table as the value.
        throw std::invalid_argument(
            fmt::format("{}: {}: an exercise with [protocol] require_server = false has no server "
                        "(remove the [{}] table)",
                        source_name, table, table));
      }
    }
  }
  for (const TomlReader& n : top.TableArray("node", kNodeKeys)) {
    c.nodes.push_back(ReadProcess(n, base, true, size_x_m, size_z_m));
  }
  if (c.nodes.empty()) top.Fail("node", "an exercise needs at least one [[node]]");
  if (auto v = top.OptionalTable("view", {"name", "site", "host", "http_address", "http_port"})) {
    ViewConfig view;
    view.http_address = v->String("http_address", "127.0.0.1");
    view.http_port = static_cast<int>(v->Int("http_port", 8480, 1, 65535));
    view.process = ReadProcess(*v, base, false, 0.0, 0.0);
    c.view = std::move(view);
  }
  if (auto d = top.OptionalTable(
          "dis",
          {"name", "site", "host", "bind_address", "udp_port", "destination", "interface_address",
           "multicast_ttl", "dis_exercise_id", "import_craters", "latitude_deg", "longitude_deg",
           "height_m", "feature_period_ms", "bundle_max_bytes"})) {
    c.dis = ReadDis(*d, base);
    if (c.elevation && c.ground_read) {
      const bool typed = d->Has("latitude_deg") || d->Has("longitude_deg") || d->Has("height_m");
      ApplyFileOrigin(*c.elevation, typed, *c.dis, std::string(source_name));
    }
  }
  top.Finish();

  std::set<std::string> names;
  std::set<NodeAddress> addresses;
  std::vector<const ProcessConfig*> everyone = c.Processes();
  if (c.view) everyone.push_back(&c.view->process);
  if (c.dis) everyone.push_back(&c.dis->process);
  for (const ProcessConfig* p : everyone) {
    if (!names.insert(p->name).second) {
      throw std::invalid_argument(
          fmt::format("{}: process name \"{}\" is used twice", source_name, p->name));
    }
    if (!addresses.insert(p->address).second) {
      throw std::invalid_argument(fmt::format("{}: address {} (of \"{}\") is used twice",
                                              source_name, p->address.ToString(), p->name));
    }
  }
  return c;
}

ExerciseConfig LoadExerciseConfig(const std::filesystem::path& path, GroundReading ground) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    throw std::invalid_argument(fmt::format("{}: cannot read the exercise config", path.string()));
  }
  std::ostringstream text;
  text << in.rdbuf();
  // absolute() first: a bare file name has an empty parent, which absolute() refuses.
  return ParseExerciseConfig(text.str(), path.string(),
                             std::filesystem::absolute(path).parent_path(), ground);
}

}  // namespace dt
