// Vehicle orientation: two-point and six-point pitch, roll and elevation (thesis II.B, III.B).
#pragma once

#include <array>
#include <cstdint>

namespace dt {

enum class OrientationMethod : uint8_t { kTwoPoint = 0, kSixPoint = 1 };

// A point fixed to the vehicle: metres ahead of the centre and metres to its right.
struct BodyPoint {
  double ahead_m = 0.0;
  double right_m = 0.0;
};

// A point on the ground plane (x east, z north).
struct GroundPoint {
  double x_m = 0.0;
  double z_m = 0.0;
};

// Where a body point of a vehicle at (x, z) heading `heading_rad` stands on the ground.
GroundPoint ToGround(double x_m, double z_m, double heading_rad, BodyPoint p);

// The six orientation points of thesis figure 9, in this order.
enum SixPoint : int {
  kFrontLeft = 0,
  kFrontRight = 1,
  kMiddleLeft = 2,
  kMiddleRight = 3,
  kRearLeft = 4,
  kRearRight = 5,
};
// The four corners (tires) among the six points.
inline constexpr std::array<SixPoint, 4> kCorners = {kFrontLeft, kFrontRight, kRearLeft,
                                                     kRearRight};

// Corners and side centres of a length x width footprint.
std::array<BodyPoint, 6> SixPointLayout(double length_m, double width_m);
// The two sampled points of thesis figure 1: half a length ahead, half a width to the right.
std::array<BodyPoint, 2> TwoPointLayout(double length_m, double width_m);

// Pitch is positive nose up, roll positive right side down (docs/conventions.md); elevation is
// the height of the footprint centre's underside.
struct Orientation {
  double pitch_rad = 0.0;
  double roll_rad = 0.0;
  double elevation_m = 0.0;
  OrientationMethod method = OrientationMethod::kTwoPoint;
};

// Thesis figure 1: pitch from centre to the front point, roll from centre to the right point;
// the vehicle stands at the centre's elevation.
Orientation TwoPointOrientation(double length_m, double width_m, double centre_m, double front_m,
                                double right_m);

// Thesis figure 9. Heights indexed by SixPoint. Pitch: the front, middle and rear pairs are
// averaged; travelling forward (reversing = false) the pitch is the greater of the middle-to-front
// and rear-to-front angles; reversing mirrors this with the rear as the leading end. Roll: from the
// highest point on each side, so a side stays lifted while any of its points is. Elevation: the
// lowest that keeps every point at or below the tilted underside, so no part sinks.
Orientation SixPointOrientation(double length_m, double width_m, const std::array<double, 6>& h_m,
                                bool reversing);

// Least-squares plane through the four corner heights (indexed by SixPoint; middle entries are
// ignored): pitch from the front and rear averages, roll from the left and right averages. Used
// for the tilt of a vehicle falling off a bridge.
Orientation CornerPlaneTilt(double length_m, double width_m, const std::array<double, 6>& h_m);

}  // namespace dt
