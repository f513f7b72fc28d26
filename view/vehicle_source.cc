#include "view/vehicle_source.h"

namespace dt {

nlohmann::json VehicleView::ToJson() const {
  // An array, not an object: a page may receive thousands a tick (docs/view.md "Messages").
  return nlohmann::json::array({id, owner, type, x_m, z_m, heading_rad, speed_mps, alive});
}

}  // namespace dt
