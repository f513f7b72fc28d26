// SharedVehicleSource: the live view's vehicles from the exercise's VehicleState PDUs, dead
// reckoned and settled on the view's own terrain as any node holds remote vehicles.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "base/feature_id.h"
#include "terrain/terrain.h"
#include "transport/pdu_bus.h"
#include "vehicle/remote_vehicles.h"
#include "view/vehicle_source.h"

namespace dt {

class SharedVehicleSource : public VehicleSource {
 public:
  // Subscribes to VehicleState on `bus` (which must outlive this); `names` names the owners.
  SharedVehicleSource(PduBus& bus, std::map<NodeAddress, std::string> names,
                      DeadReckoningThresholds thresholds);

  // Dead reckons every vehicle to now_s on `terrain` and drops those not heard for the timeout.
  void Tick(const Terrain& terrain, double now_s);
  std::vector<VehicleView> Vehicles() override;

  const RemoteVehicles& remote() const { return remote_; }

 private:
  std::map<NodeAddress, std::string> names_;
  RemoteVehicles remote_;
  double now_s_ = 0.0;
};

}  // namespace dt
