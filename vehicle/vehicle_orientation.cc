#include "vehicle/vehicle_orientation.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace dt {

GroundPoint ToGround(double x_m, double z_m, double heading_rad, BodyPoint p) {
  const double c = std::cos(heading_rad);
  const double s = std::sin(heading_rad);
  // Ahead is (cos h, sin h); right is direction h - pi/2, i.e. (sin h, -cos h).
  return {x_m + p.ahead_m * c + p.right_m * s, z_m + p.ahead_m * s - p.right_m * c};
}

std::array<BodyPoint, 6> SixPointLayout(double length_m, double width_m) {
  const double a = length_m / 2.0;
  const double r = width_m / 2.0;
  std::array<BodyPoint, 6> out;
  out[kFrontLeft] = {a, -r};
  out[kFrontRight] = {a, r};
  out[kMiddleLeft] = {0.0, -r};
  out[kMiddleRight] = {0.0, r};
  out[kRearLeft] = {-a, -r};
  out[kRearRight] = {-a, r};
  return out;
}

std::array<BodyPoint, 2> TwoPointLayout(double length_m, double width_m) {
  return {BodyPoint{length_m / 2.0, 0.0}, BodyPoint{0.0, width_m / 2.0}};
}

Orientation TwoPointOrientation(double length_m, double width_m, double centre_m, double front_m,
                                double right_m) {
  Orientation o;
  o.method = OrientationMethod::kTwoPoint;
  o.pitch_rad = std::atan2(front_m - centre_m, length_m / 2.0);
  o.roll_rad = std::atan2(centre_m - right_m, width_m / 2.0);
  o.elevation_m = centre_m;
  return o;
}

Orientation SixPointOrientation(double length_m, double width_m, const std::array<double, 6>& h,
                                bool reversing) {
  const double front = (h[kFrontLeft] + h[kFrontRight]) / 2.0;
  const double middle = (h[kMiddleLeft] + h[kMiddleRight]) / 2.0;
  const double rear = (h[kRearLeft] + h[kRearRight]) / 2.0;
  const double half = length_m / 2.0;
  Orientation o;
  o.method = OrientationMethod::kSixPoint;
  if (!reversing) {
    o.pitch_rad = std::max(std::atan2(front - middle, half), std::atan2(front - rear, length_m));
  } else {
    // The rear leads: the same rule with the ends swapped, then seen from the front again.
    o.pitch_rad = -std::max(std::atan2(rear - middle, half), std::atan2(rear - front, length_m));
  }
  const double left = std::max({h[kFrontLeft], h[kMiddleLeft], h[kRearLeft]});
  const double right = std::max({h[kFrontRight], h[kMiddleRight], h[kRearRight]});
  o.roll_rad = std::atan2(left - right, width_m);

  // The underside at body point (a, r) stands at y + a tan(pitch) - r tan(roll).
  const double tp = std::tan(o.pitch_rad);
  const double tr = std::tan(o.roll_rad);
  const auto layout = SixPointLayout(length_m, width_m);
  double y = -std::numeric_limits<double>::infinity();
  for (int k = 0; k < 6; ++k) {
    y = std::max(y, h[k] - layout[k].ahead_m * tp + layout[k].right_m * tr);
  }
  o.elevation_m = y;
  return o;
}

Orientation CornerPlaneTilt(double length_m, double width_m, const std::array<double, 6>& h) {
  const double front = (h[kFrontLeft] + h[kFrontRight]) / 2.0;
  const double rear = (h[kRearLeft] + h[kRearRight]) / 2.0;
  const double left = (h[kFrontLeft] + h[kRearLeft]) / 2.0;
  const double right = (h[kFrontRight] + h[kRearRight]) / 2.0;
  Orientation o;
  o.method = OrientationMethod::kSixPoint;
  o.pitch_rad = std::atan2(front - rear, length_m);
  o.roll_rad = std::atan2(left - right, width_m);
  o.elevation_m = (front + rear) / 2.0;
  return o;
}

}  // namespace dt
