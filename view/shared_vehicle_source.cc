#include "view/shared_vehicle_source.h"

#include <cmath>

#include "pdu/conversion.h"
#include "pdu/vehicle_state.h"

namespace dt {

SharedVehicleSource::SharedVehicleSource(PduBus& bus, std::map<NodeAddress, std::string> names,
                                         DeadReckoningThresholds thresholds)
    : names_(std::move(names)), remote_(thresholds) {
  // Validated and authenticated by the bus, like every PDU; the view owns no vehicle, so every
  // vehicle it holds is remote.
  bus.Subscribe<dtpdu::vehicle_state_t>([this](const dtpdu::vehicle_state_t& pdu) {
    (void)remote_.Apply(FromPdu(pdu.sender), FromVehicleState(pdu), now_s_);
  });
}

void SharedVehicleSource::Tick(const Terrain& terrain, double now_s) {
  now_s_ = now_s;
  (void)remote_.Tick(terrain, now_s);
}

std::vector<VehicleView> SharedVehicleSource::Vehicles() {
  std::vector<VehicleView> out;
  out.reserve(remote_.vehicles().size());
  for (const auto& [id, v] : remote_.vehicles()) {
    auto name = names_.find(v.owner);
    const std::string owner = name == names_.end() ? v.owner.ToString() : name->second;
    const auto& vel = v.state.velocity_mps;
    out.push_back(
        {.id = owner + "/" + id.ToString(),
         .owner = owner,
         .type = v.type.name,
         .x_m = v.pose.location_m[0],
         .z_m = v.pose.location_m[2],
         .heading_rad = v.pose.heading_rad,
         .speed_mps = std::hypot(vel[0], vel[1], vel[2]),
         .alive = (v.state.appearance & appearance::kDamageMask) != appearance::kDestroyed});
  }
  return out;
}

}  // namespace dt
