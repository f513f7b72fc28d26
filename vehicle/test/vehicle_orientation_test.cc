#include "vehicle/vehicle_orientation.h"

#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

namespace dt {
namespace {

constexpr double kL = 8.0;  // length
constexpr double kW = 4.0;  // width

// Heights of the six points on the plane y = y0 + sx * ahead - sr * right.
std::array<double, 6> Plane(double y0, double slope_ahead, double slope_right) {
  std::array<double, 6> h{};
  const auto layout = SixPointLayout(kL, kW);
  for (int k = 0; k < 6; ++k) {
    h[k] = y0 + slope_ahead * layout[k].ahead_m + slope_right * layout[k].right_m;
  }
  return h;
}

TEST(VehicleOrientation, TwoAndSixPointAgreeOnAPlaneForwardAndReverse) {
  // Nose up 0.1 per metre, right side down 0.2 per metre.
  const auto h = Plane(5.0, 0.1, -0.2);
  const Orientation two = TwoPointOrientation(kL, kW, 5.0, 5.0 + 0.1 * kL / 2, 5.0 - 0.2 * kW / 2);
  EXPECT_EQ(two.method, OrientationMethod::kTwoPoint);
  EXPECT_NEAR(two.pitch_rad, std::atan(0.1), 1e-12);
  EXPECT_NEAR(two.roll_rad, std::atan(0.2), 1e-12);
  EXPECT_DOUBLE_EQ(two.elevation_m, 5.0);
  for (bool reversing : {false, true}) {
    const Orientation six = SixPointOrientation(kL, kW, h, reversing);
    EXPECT_EQ(six.method, OrientationMethod::kSixPoint);
    EXPECT_NEAR(six.pitch_rad, two.pitch_rad, 1e-12) << reversing;
    EXPECT_NEAR(six.roll_rad, two.roll_rad, 1e-12) << reversing;
    EXPECT_NEAR(six.elevation_m, 5.0, 1e-12) << reversing;
  }
}

TEST(VehicleOrientation, RollFollowsTheHighestPointOfEachSide) {
  // Only the rear-left point is lifted by 1.5 m: the whole left side stays up.
  std::array<double, 6> h{};
  h[kRearLeft] = 1.5;
  const Orientation o = SixPointOrientation(kL, kW, h, false);
  EXPECT_NEAR(o.roll_rad, std::atan2(1.5, kW), 1e-12);
  // Lifting a right point as much levels it again.
  h[kFrontRight] = 1.5;
  EXPECT_NEAR(SixPointOrientation(kL, kW, h, false).roll_rad, 0.0, 1e-12);
}

TEST(VehicleOrientation, PitchTakesTheGreaterAngleTowardTheLeadingEnd) {
  // The front pair climbs 1 m onto a step while middle and rear are level.
  std::array<double, 6> h{};
  h[kFrontLeft] = h[kFrontRight] = 1.0;
  const Orientation fwd = SixPointOrientation(kL, kW, h, false);
  // Middle-to-front (1 m over 4 m) beats rear-to-front (1 m over 8 m).
  EXPECT_NEAR(fwd.pitch_rad, std::atan2(1.0, kL / 2), 1e-12);
  // Reversing, the rear leads and is level with the middle: the greater of rear-to-middle (0) and
  // rear-to-front (falling away) is 0, so the vehicle stays level, lifted by the trailing front.
  const Orientation rev = SixPointOrientation(kL, kW, h, true);
  EXPECT_NEAR(rev.pitch_rad, 0.0, 1e-12);
  EXPECT_NEAR(rev.elevation_m, 1.0, 1e-12);
  // Mirror image: the same step under the rear, reversing, gives the forward case negated.
  std::array<double, 6> m{};
  m[kRearLeft] = m[kRearRight] = 1.0;
  EXPECT_NEAR(SixPointOrientation(kL, kW, m, true).pitch_rad, -fwd.pitch_rad, 1e-12);
  EXPECT_NEAR(SixPointOrientation(kL, kW, m, false).pitch_rad, -rev.pitch_rad, 1e-12);
}

TEST(VehicleOrientation, NoPointSinksBelowTheUnderside) {
  std::array<double, 6> h = {0.3, -0.2, 1.1, 0.0, 0.7, 2.0};
  for (bool reversing : {false, true}) {
    const Orientation o = SixPointOrientation(kL, kW, h, reversing);
    const auto layout = SixPointLayout(kL, kW);
    double lowest_gap = INFINITY;
    for (int k = 0; k < 6; ++k) {
      const double underside = o.elevation_m + layout[k].ahead_m * std::tan(o.pitch_rad) -
                               layout[k].right_m * std::tan(o.roll_rad);
      EXPECT_GE(underside, h[k] - 1e-12) << k;
      lowest_gap = std::min(lowest_gap, underside - h[k]);
    }
    // And the vehicle rests on at least one point rather than floating.
    EXPECT_NEAR(lowest_gap, 0.0, 1e-12);
  }
}

TEST(VehicleOrientation, CornerPlaneTiltUsesTheFourCorners) {
  std::array<double, 6> h{};
  h[kFrontLeft] = h[kRearLeft] = 6.0;  // left corners on a deck 6 m up, right on the ground
  h[kMiddleRight] = 100.0;             // ignored
  const Orientation t = CornerPlaneTilt(kL, kW, h);
  EXPECT_NEAR(t.roll_rad, std::atan2(6.0, kW), 1e-12);
  EXPECT_NEAR(t.pitch_rad, 0.0, 1e-12);
}

TEST(VehicleOrientation, ToGroundPutsTheRightSideClockwise) {
  const GroundPoint p = ToGround(10, 20, std::numbers::pi / 2, {2.0, 1.0});  // heading north
  EXPECT_NEAR(p.x_m, 11.0, 1e-12);  // right of north is east
  EXPECT_NEAR(p.z_m, 22.0, 1e-12);
}

}  // namespace
}  // namespace dt
