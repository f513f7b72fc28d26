// ControlCommand: one control-socket request line, parsed and checked before anything runs.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "base/feature_id.h"
#include "base/result.h"
#include "runtime/control_protocol.h"
#include "runtime/feature_edit.h"
#include "runtime/node_actions.h"
#include "terrain/feature_params.h"

namespace dt {

enum class ControlVerb {
  kCreate,     // crater / berm / bridge with positional values
  kUpdate,     // update <id> key=value ...
  kDestroy,    // destroy <id>
  kBreach,     // breach <id> <gap_start_m> <gap_width_m>
  kDrive,      // drive <vehicle> <speed_mps> <heading_rate_deg_s>
  kStatus,     // status
  kDigest,     // digest
  kFeatures,   // features: every live feature ID, one a line
  kRender,     // render <file.png>
  kLoss,       // loss <drop_probability>
  kPartition,  // partition <site:host> ...: drop everything received from these nodes
  kHeal,       // heal: end partitions
  kPing,       // ping
  kExport,     // export <file.dtt>: the server saves its terrain as a terrain file
  kImport,     // import <file.dtt>: the server issues a terrain file's features
  kQuit,       // quit
  kVehicles,   // vehicles: local and remote vehicles, one a line (nodes)
  kSpawn,      // spawn <type> <x_m> <z_m> <heading_deg> [physical|light]
  kRemove,     // remove <vehicle>
  kBlade,      // blade <vehicle> down <depth_m> | blade <vehicle> up
};

struct ControlCommand {
  ControlVerb verb = ControlVerb::kPing;
  FeatureParams params;  // create
  FeatureId target;      // update, destroy, breach
  FeatureEdit edit;      // update
  double gap_start_m = 0.0;
  double gap_width_m = 0.0;
  int vehicle = 0;
  double speed_mps = 0.0;
  double heading_rate_rad_s = 0.0;
  std::string path;                     // render, export, import
  double drop_probability = 0.0;        // loss
  std::vector<NodeAddress> nodes;       // partition
  SpawnRequest spawn;                   // spawn
  std::optional<double> blade_depth_m;  // blade: the depth when lowered, nullopt when raised
};

// The usage text listing every command (docs/node.md "Control socket").
std::string ControlUsage();

// Parses a line; an unknown verb, a wrong argument count, a value that is not a finite number,
// or invalid feature parameters is an Error naming the argument and value.
Result<ControlCommand> ParseControlCommand(std::string_view line);

// "site:host:number" (each a decimal number in range, number >= 1).
Result<FeatureId> ParseFeatureId(std::string_view text);
// "site:host".
Result<NodeAddress> ParseNodeAddress(std::string_view text);

// Runs a feature, drive, spawn or remove command against the node. The reply body of a
// create or breach lists the new IDs, one a line; that of a drive names each value the vehicle
// clamped to its type's limits ("speed 1e+30 m/s clamped to 18 m/s, the tank's top speed").
ControlReply RunFeatureCommand(const ControlCommand& command, NodeActions& actions);

}  // namespace dt
