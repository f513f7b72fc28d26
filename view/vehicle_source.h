// VehicleSource: where the live view gets vehicles from, so a vehicle layer plugs in through one
// small interface (docs/view.md "Vehicles").
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace dt {

// One vehicle as the page draws it: an oriented marker in its owner's colour, dead ones marked.
struct VehicleView {
  std::string id;     // unique in the exercise, e.g. "node-1/0"
  std::string owner;  // the process that drives it (its colour on the page)
  std::string type;   // "tank", "truck", "jeep"
  double x_m = 0.0, z_m = 0.0, heading_rad = 0.0, speed_mps = 0.0;
  bool alive = true;
  bool operator==(const VehicleView&) const = default;
  // [id, owner, type, x, z, heading, speed, alive]: an array, the page's vehicle message.
  nlohmann::json ToJson() const;
};

// Polled by the view's loop at its tick rate (the page receives a vehicle delta whenever the
// list differs). The view's source is the exercise's VehicleState PDUs
// (view/shared_vehicle_source.h); another (a recording, say) would plug in here alike.
class VehicleSource {
 public:
  virtual ~VehicleSource() = default;
  virtual std::vector<VehicleView> Vehicles() = 0;
};

}  // namespace dt
