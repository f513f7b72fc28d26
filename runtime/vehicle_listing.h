// VehicleListing: the `dt_ctl vehicles` reply, one line a vehicle (docs/node.md), written by
// nodes and the DIS gateway and read back into values for the drills' vehicle actions
// (docs/launcher.md "Vehicle actions").
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "base/result.h"

namespace dt {

struct ListedVehicle {
  bool local = false;  // the process's own (a "local" line) or another's ("remote")
  size_t index = 0;    // local: its place in the process's list (what `remove` takes)
  std::string entity;  // site:host:number
  std::string type;
  std::string owner;  // site:host
  double x_m = 0.0, y_m = 0.0, z_m = 0.0;
  double heading_deg = 0.0, pitch_deg = 0.0, roll_deg = 0.0;
  double speed_mps = 0.0;
  double model_error_m = 0.0;
  double age_s = 0.0;  // remote: since the last state arrived (0 for a local vehicle)
  bool alive = true;
  // Written, not read back.
  uint64_t sent = 0;     // local: states sent
  bool settled = false;  // remote: y, pitch and roll from the holder's own terrain
  uint64_t updates = 0;  // remote: states received
};

// The line `v` is listed as: "local <index> <entity> <type> owner=... sent=<n>" or "remote
// <entity> <type> owner=... settled=<0|1> age_s=<s> updates=<n>", lengths in centimetres,
// angles in hundredths of a degree, model error in millimetres.
std::string VehicleLine(const ListedVehicle& v);

// One entry per line; an error naming the line for anything that is not a vehicle line with
// every key above (an empty reply is no vehicles). A page's "<n> more" line is skipped: the
// entries are the page's.
Result<std::vector<ListedVehicle>> ParseVehicleListing(std::string_view body);

// A page of a listing (`vehicles [--owner <site:host>] [--offset <n>] [--limit <n> | --all]`): the
// lines of one owner, or all, from `offset` on, at most `limit` of them. The control socket's
// default is everything (the drills read whole listings); dt_ctl asks for kDefaultVehicleLimit
// unless told otherwise, since 30 000 vehicles are 6 MB of lines.
struct VehiclePage {
  std::string owner;  // site:host; empty: every owner
  size_t offset = 0;
  std::optional<size_t> limit;  // nullopt: every line from offset on
  bool operator==(const VehiclePage&) const = default;
};
inline constexpr size_t kDefaultVehicleLimit = 1000;

// The page of a listing written by VehicleLine: the chosen lines, then, when lines of the
// selection were left out after the page, "<n> more (--offset <next>)". The whole listing,
// unchanged, for the default page.
std::string PageVehicleListing(std::string_view listing, const VehiclePage& page);

// The larger of |pitch| and |roll|, degrees.
double TiltDeg(const ListedVehicle& v);

}  // namespace dt
