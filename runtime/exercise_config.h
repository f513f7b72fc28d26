// ExerciseConfig: one exercise (terrain, transport, protocol timing, server and nodes) read from
// TOML.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "base/feature_id.h"
#include "pdu/exercise_key.h"
#include "runtime/exercise_ground.h"
#include "terrain/base_ground.h"
#include "terrain/friction_table.h"
#include "terrain/random_terrain.h"
#include "terrain/terrain_file.h"
#include "transport/fault_model.h"
#include "vehicle/dead_reckoning_policy.h"
#include "vehicle/simulated_vehicle.h"
#include "vehicle/wander.h"

namespace dt {

// A vehicle a node drives from the start (vehicle/vehicle_type.h names the types).
struct VehicleConfig {
  std::string type = "tank";
  double x_m = 0.0;
  double z_m = 0.0;
  double heading_rad = 0.0;
  VehicleModel model = VehicleModel::kPhysical;  // docs/vehicles.md "Choosing the model"
};

// A group of autonomous vehicles a node owns from the start (docs/vehicles.md "Autonomous
// groups"): `count` vehicles of one type placed in `area` from `seed`, each wandering it.
struct VehicleGroupConfig {
  std::string type = "truck";
  int count = 1;    // 1 .. kMaxGroupVehicles
  WanderArea area;  // inside the terrain; the whole terrain when the file gives none
  uint64_t seed = 1;
  // Physical by default: a group obeys the terrain; "light" only where a file asks for it (it does
  // not: docs/vehicles.md "Autonomous groups").
  VehicleModel model = VehicleModel::kPhysical;
};
inline constexpr int kMaxGroupVehicles = 10000;  // per group
inline constexpr int kMaxNodeVehicles = 60000;   // vehicles and groups of one node together

// One process of the exercise: the server, the standby or a node.
struct ProcessConfig {
  std::string name;  // "server", "node-1": names logs, the control socket and output prefixes
  NodeAddress address;
  std::filesystem::path scenario;  // nodes only; empty: none (absolute, resolved by the loader)
  std::vector<VehicleConfig> vehicles;
  std::vector<VehicleGroupConfig> groups;  // their vehicles follow `vehicles` in the node's list
  // vehicles.size() plus every group's count: the node's vehicles at the start.
  int start_vehicle_count() const;
};

// The live view (docs/view.md): an observer replica that serves a web page.
struct ViewConfig {
  ProcessConfig process;                   // name, address (a member with role observer)
  std::string http_address = "127.0.0.1";  // only this host by default
  int http_port = 8480;
};

// The DIS gateway (docs/dis.md "The gateway"): an observer replica (a node member when it imports
// craters) that speaks DIS 7 on UDP. The geodetic origin of the terrain lives here: only the
// gateway places the terrain on the Earth. With an elevation file the origin is the file's
// (a typed one must agree within kOriginToleranceM, docs/real-ground.md).
struct DisConfig {
  ProcessConfig process;                        // name, address
  std::string bind_address = "0.0.0.0";         // the UDP socket's local address
  int udp_port = 3000;                          // DIS's customary port, sent to and received on
  std::string destination = "127.255.255.255";  // a broadcast address or a multicast group
  std::string interface_address = "127.0.0.1";  // multicast: the interface joined and sent on
  int multicast_ttl = 1;
  uint8_t dis_exercise_id = 1;  // the DIS header's exercise ID (not [exercise] id)
  bool import_craters = false;  // outside Point Object State craters become features
  double latitude_deg = 0.0;    // where terrain (0, 0, 0) lies on WGS-84
  double longitude_deg = 0.0;
  double height_m = 0.0;
  int feature_period_ms = 5000;  // every live feature's Object State is sent again this often
  // 0: one PDU per datagram (every DIS receiver reads it). Else PDUs bundled (IEEE 1278.2) into
  // datagrams of at most this many bytes (docs/dis.md "Bundling").
  int bundle_max_bytes = 0;
  bool multicast() const;  // destination is in 224.0.0.0/4
};

// Protocol timing (docs/protocol.md); the values map onto ReplicaConfig.
struct ProtocolTiming {
  int max_feature_period_ms = 500;
  int silence_ms = 2000;
  int playback_retry_ms = 500;
  int playback_window = 256;
  int playback_window_max = 8192;     // a catch-up's window grows up to this on long round trips
  int anti_entropy_period_ms = 1000;  // 0: anti-entropy off
  int gap_give_up_ms = 30000;         // 0: never (docs/protocol.md, "Lost changes")
};

// How the exercise's PDUs are authenticated (docs/pdu.md "Authentication"): [auth] names a key
// file, or says mode = "none" to run without one. There is no default: the table is required.
struct AuthSettings {
  bool keyless = false;                    // mode = "none"
  std::filesystem::path key_file;          // absolute; empty when keyless
  std::shared_ptr<const ExerciseKey> key;  // read when the file is loaded; null when keyless
  int clock_tolerance_ms = 30000;          // PduAuthConfig::clock_tolerance
};

// [hosts]: where dt_launch and dt_drill run the processes (docs/deploy.md). `none`: every process
// on the launcher's own network; `lan`: each in a network namespace of its own ("host") on one
// bridge; `wan`: one bridge per site, the sites joined by a router namespace.
enum class HostsMode { kNone, kLan, kWan };
std::optional<HostsMode> ParseHostsMode(std::string_view text);  // "none", "lan", "wan"
std::string_view HostsModeName(HostsMode mode);

struct HostsConfig {
  HostsMode mode = HostsMode::kNone;
  double rate_mbit = 100.0;  // each host's link rate (tc tbf)
  int queue_ms = 50;         // the longest a packet waits in a link's queue (tbf latency)
};

struct ExerciseConfig {
  std::filesystem::path source;  // the file read
  std::string name;
  uint8_t exercise_id = 1;
  std::string transport_url;      // transport/transport.h MakeTransport
  std::filesystem::path run_dir;  // sockets, databases, renders (absolute)
  int tick_hz = 30;
  // The friction table vehicles grip by: [exercise] friction_file, read at load, or the built-in
  // configs/friction.toml when the file names none (friction_file then empty). Never null.
  std::filesystem::path friction_file;
  std::shared_ptr<const FrictionTable> friction;
  // [terrain]: posts_per_side (a square) or posts_x and posts_z, spacing, relief, seed. With an
  // elevation file, posts and spacing are the file's layout's.
  RandomTerrainParams terrain;
  // [terrain] ground_file: a saved terrain (terrain/terrain_file.h, what the server's `export`
  // writes) the exercise starts on instead of random ground (absolute; empty: none). Only its
  // header is read at load (ground_file_shape): the grid's posts and spacing are then
  // `terrain`'s. BuildExerciseGround reads the ground, through the host's ground cache where
  // GroundFileCacheDir names one, so a process that never builds the ground never reads it.
  std::filesystem::path ground_file;
  std::optional<TerrainFileShape> ground_file_shape;  // absent when the ground was skipped
  // [terrain] ground_cache_dir beside a ground_file (relative to the exercise file; absolute here).
  std::filesystem::path ground_file_cache_dir;
  // False when the file was read with GroundReading::kSkip: no ground can be built from it.
  bool ground_read = true;
  // [terrain] elevation_file and its keys (docs/real-ground.md); absent for random ground.
  std::optional<ElevationTerrain> elevation;
  ProtocolTiming protocol;
  AuthSettings auth;
  FaultConfig faults;  // injected on receipt by every process (transport/faulty_transport.h)
  // Shared vehicles' dead reckoning ([vehicles], docs/vehicles.md "Shared vehicles").
  DeadReckoningThresholds dead_reckoning;
  uint64_t fault_seed = 1;
  HostsConfig hosts;  // read by the launchers only
  // Absent exactly when the file says [protocol] require_server = false: an exercise without a
  // server (a replay of a recording, docs/pdu.md), whose nodes sign on with what they hear.
  std::optional<ProcessConfig> server;
  std::optional<ProcessConfig> standby;
  std::vector<ProcessConfig> nodes;
  std::optional<ViewConfig> view;  // [view]: the live view, started by the launcher last
  std::optional<DisConfig> dis;    // [dis]: the DIS gateway, started with the view

  // The terrain covers [0, terrain_size_x_m()] x [0, terrain_size_z_m()].
  double terrain_size_x_m() const { return (terrain.posts_x - 1) * terrain.spacing_m; }
  double terrain_size_z_m() const { return (terrain.posts_z - 1) * terrain.spacing_m; }
  // ReplicaConfig::require_server: nodes wait for a server's answer to sign on.
  bool require_server() const { return server.has_value(); }
  // The server and the standby (each if any), then every node, in that order.
  std::vector<const ProcessConfig*> Processes() const;
  // nullptr if no process has this name (the view's and the gateway's included).
  const ProcessConfig* FindProcess(std::string_view name) const;
  // The control socket of a process: <run_dir>/<name>.sock.
  std::filesystem::path SocketPath(std::string_view name) const;
};

// What reading the exercise file reads of the ground. kRead: the ground_file's header or the
// elevation file's (GDAL's probe), for the grid's shape and the elevation file's origin; never the
// ground itself (BuildExerciseGround). kSkip: neither file is opened, for a process that needs
// only the names, addresses and keys (dt_ctl): the grid's shape is then unknown, vehicles are not
// checked against it, and ground_read is false.
enum class GroundReading { kRead, kSkip };

// Parses TOML text. Relative paths (scenarios, the key file) resolve against base_dir; a relative
// run_dir resolves against the current directory. The key file is read here. Throws
// std::invalid_argument naming `source_name`, the key and the offending value for a syntax
// error, a missing or mistyped key, a value out of range, an unknown key, duplicate process names
// or addresses, a ground_file whose header does not read (its path and the reason; the rest of
// the file is checked where the ground is built) or that comes with grid keys, a missing [server]
// (unless [protocol] require_server = false) or a [server] or [standby] in an exercise without a
// server, a missing [auth] table, a key file that cannot be read or is too short (the message names
// its path and length), or a bad friction file.
ExerciseConfig ParseExerciseConfig(std::string_view toml_text, std::string_view source_name,
                                   const std::filesystem::path& base_dir,
                                   GroundReading ground = GroundReading::kRead);

// Replaces the transport URL and run_dir when the strings are non-empty (command-line flags).
// Throws std::invalid_argument for a transport that is not udpm://, dds:// or memq://.
void ApplyOverrides(ExerciseConfig& exercise, const std::string& transport_url,
                    const std::string& run_dir);

// Reads and parses a file (relative paths resolve against its folder). Throws
// std::invalid_argument as ParseExerciseConfig, or if the file cannot be read.
ExerciseConfig LoadExerciseConfig(const std::filesystem::path& path,
                                  GroundReading ground = GroundReading::kRead);

}  // namespace dt
