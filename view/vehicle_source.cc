#include "view/vehicle_source.h"

namespace dt {

nlohmann::json VehicleView::ToJson() const {
  return {{"id", id}, {"owner", owner},         {"type", type},       {"x", x_m},
          {"z", z_m}, {"heading", heading_rad}, {"speed", speed_mps}, {"alive", alive}};
}

}  // namespace dt
