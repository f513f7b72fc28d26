// ControlCommand: one control-socket request line, parsed and checked before anything runs.
#pragma once

#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "base/feature_id.h"
#include "base/result.h"
#include "runtime/control_protocol.h"
#include "runtime/feature_edit.h"
#include "runtime/node_actions.h"
#include "runtime/vehicle_listing.h"
#include "terrain/feature_params.h"

namespace dt {

// What a command does. runtime/control_command.cc holds the one table of command words: each
// word's verb, arguments, help and parser; ControlUsage() and ParseControlCommand() come from it.
enum class ControlVerb {
  kCreate,  // crater, ditch, berm_line, area, berm, bridge: one command word per feature type
  kUpdate,
  kDestroy,
  kBreach,
  kDrive,
  kStatus,
  kDigest,
  kFeatures,
  kRender,
  kLoss,
  kPartition,
  kHeal,
  kPing,
  kExport,
  kImport,
  kQuit,
  kVehicles,
  kSpawn,
  kRemove,
  kBlade,
  kCount,  // not a verb: how many there are (keep it last)
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
  VehiclePage vehicle_page;             // vehicles: which lines the reply holds
};

// One command word of the control socket: a row of the verb table.
struct ControlVerbSpec {
  std::string_view word;      // the command's first word
  ControlVerb verb;           // what ParseControlCommand sets for it
  std::string_view synopsis;  // its arguments, as the usage shows them
  std::string_view help;      // what it does, one line
  bool joins_usage_line;      // listed on the previous row's usage line, after " | "
  // Reads the whole line split into words (words[0] is `word`); the verb is set by the caller.
  Result<ControlCommand> (*parse)(const ControlVerbSpec& spec,
                                  const std::vector<std::string_view>& words);
};

// Every command word, in the usage's order: each verb has one row (kCreate one per feature
// type with a command of its own).
std::span<const ControlVerbSpec> ControlVerbTable();

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
