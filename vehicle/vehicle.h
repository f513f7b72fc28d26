// Vehicle: one vehicle's state and kinematic driving on a terrain.
#pragma once

#include <array>

#include "base/feature_id.h"
#include "base/result.h"
#include "vehicle/vehicle_orientation.h"
#include "vehicle/vehicle_type.h"

namespace dt {

// Kinematic: the commanded speed and heading rate are reached at once (no acceleration model).
// Position and heading change only through Step; elevation, pitch, roll, the on-bridge tag and
// death are set by the traversal (vehicle_traversal.h) from the terrain.
class Vehicle {
 public:
  // Checks the type, that the pose is finite, and that the whole footprint lies on the terrain
  // [0, terrain_size_x_m] x [0, terrain_size_z_m]. The vehicle starts at rest, alive, off any
  // bridge, at elevation 0 until the first traversal.
  static Result<Vehicle> Make(VehicleType type, double x_m, double z_m, double heading_rad,
                              double terrain_size_x_m, double terrain_size_z_m);

  const VehicleType& type() const { return type_; }
  double x_m() const { return x_m_; }
  double z_m() const { return z_m_; }
  // In (-pi, pi].
  double heading_rad() const { return heading_rad_; }
  // Negative when reversing.
  double speed_mps() const { return speed_mps_; }
  double heading_rate_rad_s() const { return heading_rate_rad_s_; }
  double terrain_size_x_m() const { return terrain_size_x_m_; }
  double terrain_size_z_m() const { return terrain_size_z_m_; }

  // Reversing means moving backwards: speed < 0. A vehicle at rest counts as forward.
  bool reversing() const { return speed_mps_ < 0.0; }
  // The direction the vehicle moves in: its heading, or heading + pi when reversing.
  double TravelDirectionRad() const;

  const Orientation& orientation() const { return orientation_; }
  double elevation_m() const { return orientation_.elevation_m; }
  double pitch_rad() const { return orientation_.pitch_rad; }
  double roll_rad() const { return orientation_.roll_rad; }

  // The on-bridge tag: the bridge whose deck the vehicle stands on, or none (number 0).
  bool on_bridge() const { return bridge_.number != 0; }
  FeatureId bridge() const { return bridge_; }
  bool alive() const { return alive_; }

  // Where a body point stands on the ground, and the six orientation points.
  GroundPoint PointAt(BodyPoint p) const;
  std::array<GroundPoint, 6> SixPoints() const;

  // Sets the commanded speed (negative = reverse) and heading rate (positive = counter-clockwise),
  // each clamped to the type's limits. Refused for non-finite values and for a dead vehicle.
  Status Command(double speed_mps, double heading_rate_rad_s);

  // Advances dt_s seconds: turns, then moves along the mean heading. A turn that would swing the
  // footprint off the terrain is not made; a move that would leave it stops at the edge. Either
  // way the vehicle stops (speed and heading rate 0). A dead vehicle does not move. Refused for a
  // non-finite or negative dt_s, or one so long that the move overflows.
  Status Step(double dt_s);

  // Used by the traversal.
  void set_orientation(const Orientation& o) { orientation_ = o; }
  void set_bridge(FeatureId id) { bridge_ = id; }
  void clear_bridge() { bridge_ = FeatureId{}; }
  void Kill();

 private:
  Vehicle(VehicleType type, double x_m, double z_m, double heading_rad, double terrain_size_x_m,
          double terrain_size_z_m);
  // True if the footprint at this pose lies on the terrain.
  bool FootprintOnTerrain(double x_m, double z_m, double heading_rad) const;

  VehicleType type_;
  double x_m_;
  double z_m_;
  double heading_rad_;
  double terrain_size_x_m_;
  double terrain_size_z_m_;
  double speed_mps_ = 0.0;
  double heading_rate_rad_s_ = 0.0;
  Orientation orientation_;
  FeatureId bridge_;
  bool alive_ = true;
};

// An angle wrapped into (-pi, pi].
double WrapAngleRad(double angle_rad);

}  // namespace dt
