// VehicleListing: a node's `dt_ctl vehicles` reply read back into values (docs/node.md), for the
// drills' vehicle actions (docs/launcher.md "Vehicle actions").
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "terrain/result.h"

namespace dt {

struct ListedVehicle {
  bool local = false;  // the node's own (a "local" line) or another node's ("remote")
  int index = -1;      // local: the vehicle's index on its node (drive, blade); remote: -1
  std::string entity;  // site:host:number
  std::string type;
  std::string owner;  // site:host
  double x_m = 0.0, y_m = 0.0, z_m = 0.0;
  double heading_deg = 0.0, pitch_deg = 0.0, roll_deg = 0.0;
  double speed_mps = 0.0;
  double model_error_m = 0.0;
  double age_s = 0.0;  // remote: since the last state arrived (0 for a local vehicle)
  bool alive = true;
};

// One entry per line; an error naming the line for anything that is not a vehicle line with
// every key above (an empty reply is no vehicles).
Result<std::vector<ListedVehicle>> ParseVehicleListing(std::string_view body);

// The larger of |pitch| and |roll|, degrees.
double TiltDeg(const ListedVehicle& v);

}  // namespace dt
