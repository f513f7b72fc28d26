#include "vehicle/vehicle_traversal.h"

#include <cmath>
#include <functional>
#include <limits>
#include <numbers>

#include <gtest/gtest.h>

#include "terrain/bridge.h"
#include "terrain/crater.h"
#include "terrain/polyline_earthwork.h"

namespace dt {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kGroundM = 10.0;
constexpr double kDt = 0.05;
constexpr FeatureId kBridgeId{1, 1, 1};

// 300 m x 300 m of flat ground 10 m up, 2 m spacing.
Terrain FlatTerrain() { return Terrain(HeightGrid(151, 2.0, static_cast<float>(kGroundM))); }

// Ramp 1 x 70..100 up to 6 m, span x 100..140 from 6 m to 8 m, ramp 2 x 140..170; z 145..155.
// Hot spot 1: x 62..78, hot spot 2: x 162..178.
FeatureParams EastBridge(double h1 = 6, double h2 = 8) {
  return FeatureParams::Bridge(100, 150, 0.0, 10, 30, 40, 30, h1, h2);
}

// The deck of EastBridge along its centre line, computed here independently.
double ExpectedDeck(double x, double h1 = 6, double h2 = 8) {
  if (x <= 100) return kGroundM + (x - 70) / 30 * h1;
  if (x <= 140) return kGroundM + h1 + (x - 100) / 40 * (h2 - h1);
  return kGroundM + h2 - (x - 140) / 30 * h2;
}

Vehicle Place(const Terrain& t, VehicleType type, double x, double z, double heading) {
  auto v =
      Vehicle::Make(std::move(type), x, z, heading, t.ground().size_x_m(), t.ground().size_z_m());
  if (!v) {
    ADD_FAILURE() << v.error().message;
    std::abort();
  }
  auto settled = SettleVehicle(t, v.value());
  if (!settled) ADD_FAILURE() << settled.error().message;
  return std::move(v).value();
}

// Drives until `done` holds (checked after each step) or `max_s` seconds pass; `each` sees every
// step. Returns false on timeout.
bool DriveUntil(const Terrain& t, Vehicle& v, const std::function<bool(const Vehicle&)>& done,
                const std::function<void(const Vehicle&, const TraversalReport&)>& each = {},
                double max_s = 120) {
  for (double s = 0; s < max_s; s += kDt) {
    auto r = DriveVehicle(t, v, kDt);
    if (!r) {
      ADD_FAILURE() << r.error().message;
      return false;
    }
    if (each) each(v, r.value());
    if (done(v)) return true;
  }
  return false;
}

const Bridge& BridgeOf(const Terrain& t) { return dynamic_cast<const Bridge&>(*t.Find(kBridgeId)); }

// A tank driven from x = 50 up ramp 1 and stopped with its centre at x >= stop_x on the centre
// line.
Vehicle TankOnSpan(const Terrain& t, double stop_x) {
  Vehicle v = Place(t, TankType(), 50, 150, 0.0);
  EXPECT_TRUE(v.Command(5, 0).ok());
  EXPECT_TRUE(DriveUntil(t, v, [&](const Vehicle& w) { return w.x_m() >= stop_x; }));
  EXPECT_TRUE(v.Command(0, 0).ok());
  auto r = SettleVehicle(t, v);
  EXPECT_TRUE(r.ok());
  EXPECT_TRUE(v.on_bridge());
  return v;
}

TEST(Traversal, TwoPointOnBareGroundSixPointNearAFeature) {
  Terrain t = FlatTerrain();
  ASSERT_TRUE(t.Add({1, 1, 9}, FeatureParams::Crater(200, 60, 10)).ok());
  Vehicle far = Place(t, TankType(), 60, 60, 0.3);
  auto r = SettleVehicle(t, far);
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(r.value().method, OrientationMethod::kTwoPoint);
  EXPECT_DOUBLE_EQ(far.elevation_m(), kGroundM);
  // The front-right corner reaches the crater's cells.
  Vehicle near = Place(t, TankType(), 188, 60, 0.0);
  r = SettleVehicle(t, near);
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(r.value().method, OrientationMethod::kSixPoint);
  // Near a bridge, even off its deck and hot spots, six-point too.
  ASSERT_TRUE(t.Add(kBridgeId, EastBridge()).ok());
  Vehicle by_bridge = Place(t, TankType(), 120, 142.5, 0.0);
  r = SettleVehicle(t, by_bridge);
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(r.value().method, OrientationMethod::kSixPoint);
  EXPECT_DOUBLE_EQ(by_bridge.elevation_m(), kGroundM);
}

TEST(Traversal, TwoPointFollowsASlope) {
  // Ground rising 0.1 per metre east.
  std::vector<float> posts(51 * 51);
  for (int j = 0; j < 51; ++j) {
    for (int i = 0; i < 51; ++i) posts[j * 51 + i] = static_cast<float>(0.2 * i);
  }
  Terrain t{HeightGrid(51, 2.0, posts)};
  Vehicle east = Place(t, JeepType(), 50, 50, 0.0);
  EXPECT_EQ(east.orientation().method, OrientationMethod::kTwoPoint);
  EXPECT_NEAR(east.pitch_rad(), std::atan(0.1), 1e-6);
  EXPECT_NEAR(east.roll_rad(), 0.0, 1e-6);
  EXPECT_NEAR(east.elevation_m(), 5.0, 1e-6);
  // Heading north the slope rises to the right (east): right side up, negative roll.
  Vehicle north = Place(t, JeepType(), 50, 50, kPi / 2);
  EXPECT_NEAR(north.pitch_rad(), 0.0, 1e-6);
  EXPECT_NEAR(north.roll_rad(), -std::atan(0.1), 1e-6);
}

TEST(Traversal, TankOnACraterWithItsLeftTrackKeepsItsRollUntilTheRearPassesTheRim) {
  Terrain t = FlatTerrain();
  const FeatureId id{1, 1, 7};
  ASSERT_TRUE(t.Add(id, FeatureParams::Crater(150, 60, 10)).ok());
  const Crater& crater = dynamic_cast<const Crater&>(*t.Find(id));
  const double rim = crater.rim_height_m();
  ASSERT_GT(rim, 1.0);
  // Heading east, left is north: the left track runs 6.65 m south of the crater's centre, over
  // its rim, while the right track (10.35 m south) stays on the ground.
  Vehicle v = Place(t, TankType(), 110, 60 - 8.5, 0.0);
  ASSERT_TRUE(v.Command(4, 0).ok());
  auto offset = [&](GroundPoint p) { return crater.OffsetAboveGround(p.x_m, p.z_m).value_or(0.0); };
  const double full_roll = std::atan2(rim, TankType().width_m);
  int rear_only_on_rim = 0, after = 0, before = 0;
  ASSERT_TRUE(DriveUntil(
      t, v, [](const Vehicle& w) { return w.x_m() > 190; },
      [&](const Vehicle& w, const TraversalReport&) {
        const auto p = w.SixPoints();
        ASSERT_EQ(offset(p[kFrontRight]) + offset(p[kMiddleRight]) + offset(p[kRearRight]), 0.0);
        const bool front_off = offset(p[kFrontLeft]) == 0.0 && offset(p[kMiddleLeft]) == 0.0;
        const bool rear_on_rim = offset(p[kRearLeft]) >= rim - 1e-9;
        if (p[kFrontLeft].x_m > 150 && front_off && rear_on_rim) {
          // Front and middle are off the crater; the rear keeps the left side up, level along
          // its length and lifted so the rear-left corner rests on the rim.
          ++rear_only_on_rim;
          EXPECT_NEAR(w.pitch_rad(), 0.0, 1e-12) << w.x_m();
          EXPECT_NEAR(w.roll_rad(), full_roll, 1e-9) << w.x_m();
          EXPECT_NEAR(w.elevation_m(), kGroundM + rim / 2, 1e-9) << w.x_m();
        }
        if (p[kRearLeft].x_m > 150 + 10) {
          ++after;
          EXPECT_NEAR(w.roll_rad(), 0.0, 1e-12) << w.x_m();
          EXPECT_NEAR(w.elevation_m(), kGroundM, 1e-12) << w.x_m();
        }
        if (p[kFrontLeft].x_m < 150 - 10) {
          ++before;
          EXPECT_NEAR(w.roll_rad(), 0.0, 1e-12) << w.x_m();
        }
        EXPECT_GE(w.roll_rad(), 0.0);
      }));
  EXPECT_GE(rear_only_on_rim, 3);
  EXPECT_GT(after, 5);
  EXPECT_GT(before, 5);
}

TEST(Traversal, ReversingOverACraterMirrorsDrivingForward) {
  Terrain t = FlatTerrain();
  ASSERT_TRUE(t.Add({1, 1, 7}, FeatureParams::Crater(150, 60, 10)).ok());
  // Both move east along z = 57; one faces east going forward, the other faces west reversing.
  Vehicle fwd = Place(t, TankType(), 125, 57, 0.0);
  Vehicle rev = Place(t, TankType(), 125, 57, kPi);
  ASSERT_TRUE(fwd.Command(4, 0).ok());
  ASSERT_TRUE(rev.Command(-4, 0).ok());
  double max_pitch = 0, max_roll = 0;
  for (int i = 0; i < 300; ++i) {
    auto a = DriveVehicle(t, fwd, kDt);
    auto b = DriveVehicle(t, rev, kDt);
    ASSERT_TRUE(a.ok() && b.ok());
    ASSERT_NEAR(rev.x_m(), fwd.x_m(), 1e-9);
    ASSERT_NEAR(rev.z_m(), fwd.z_m(), 1e-9);
    // The reversing vehicle's front is the forward one's rear and its left is the other's right.
    EXPECT_NEAR(rev.pitch_rad(), -fwd.pitch_rad(), 1e-9) << fwd.x_m();
    EXPECT_NEAR(rev.roll_rad(), -fwd.roll_rad(), 1e-9) << fwd.x_m();
    EXPECT_NEAR(rev.elevation_m(), fwd.elevation_m(), 1e-9) << fwd.x_m();
    max_pitch = std::max(max_pitch, std::abs(fwd.pitch_rad()));
    max_roll = std::max(max_roll, std::abs(fwd.roll_rad()));
  }
  EXPECT_GT(fwd.x_m(), 180);
  EXPECT_GT(max_pitch, 0.1);  // the crossing did tilt the vehicles
  EXPECT_GT(max_roll, 0.05);
}

TEST(Traversal, AlignedVehicleMountsCrossesOnTheDeckAndDrivesOffTheFarEnd) {
  Terrain t = FlatTerrain();
  ASSERT_TRUE(t.Add(kBridgeId, EastBridge()).ok());
  Vehicle v = Place(t, TankType(), 50, 150, 0.0);
  ASSERT_TRUE(v.Command(5, 0).ok());
  const double half = TankType().length_m / 2;
  double mounted_at = -1, off_at = -1;
  int on_ramp = 0, on_span = 0;
  ASSERT_TRUE(DriveUntil(
      t, v, [](const Vehicle& w) { return w.x_m() > 200; },
      [&](const Vehicle& w, const TraversalReport& r) {
        EXPECT_TRUE(w.alive());
        EXPECT_NE(r.event, BridgeEvent::kFellOff);
        if (r.event == BridgeEvent::kMounted) mounted_at = w.x_m();
        if (r.event == BridgeEvent::kDroveOff) off_at = w.x_m();
        const double x = w.x_m();
        if (x < 62) {
          EXPECT_FALSE(w.on_bridge()) << x;
        }
        if (x >= 62 && x <= 170) {
          EXPECT_TRUE(w.on_bridge()) << x;
        }
        // Whole vehicle on one straight piece of deck: it stands on the deck at its centre.
        if ((x - half >= 70 && x + half <= 100) || (x - half >= 100 && x + half <= 140)) {
          (x <= 100 ? on_ramp : on_span)++;
          EXPECT_NEAR(w.elevation_m(), ExpectedDeck(x), 1e-9) << x;
          const double slope = x <= 100 ? 6.0 / 30 : 2.0 / 40;
          EXPECT_NEAR(w.pitch_rad(), std::atan(slope), 1e-9) << x;
          EXPECT_NEAR(w.roll_rad(), 0.0, 1e-12) << x;
          EXPECT_EQ(r.method, OrientationMethod::kSixPoint);
        }
        if (x > 178 + half) {
          EXPECT_DOUBLE_EQ(w.elevation_m(), kGroundM) << x;
        }
      }));
  EXPECT_GE(mounted_at, 62);
  EXPECT_LT(mounted_at, 62 + 5 * kDt + 1e-9);  // on the first step inside hot spot 1
  EXPECT_GT(off_at, 170);                      // only in the outer part of hot spot 2
  EXPECT_LT(off_at, 170 + 5 * kDt + 1e-9);
  EXPECT_FALSE(v.on_bridge());
  EXPECT_GT(on_ramp, 10);
  EXPECT_GT(on_span, 10);
}

TEST(Traversal, BackingOnAndOffWorks) {
  Terrain t = FlatTerrain();
  ASSERT_TRUE(t.Add(kBridgeId, EastBridge()).ok());
  // Facing west, reversing east: moving onto ramp 1.
  Vehicle v = Place(t, TankType(), 50, 150, kPi);
  ASSERT_TRUE(v.Command(-5, 0).ok());
  ASSERT_TRUE(DriveUntil(t, v, [](const Vehicle& w) { return w.x_m() >= 120; }));
  EXPECT_TRUE(v.on_bridge());
  EXPECT_NEAR(v.elevation_m(), ExpectedDeck(v.x_m()), 1e-9);
  // Now forward (west) back down ramp 1: off in the outer part of hot spot 1.
  ASSERT_TRUE(v.Command(5, 0).ok());
  double off_at = -1;
  ASSERT_TRUE(DriveUntil(
      t, v, [](const Vehicle& w) { return w.x_m() < 40; },
      [&](const Vehicle& w, const TraversalReport& r) {
        EXPECT_NE(r.event, BridgeEvent::kFellOff);
        if (r.event == BridgeEvent::kDroveOff) off_at = w.x_m();
        if (w.x_m() >= 70) {
          EXPECT_TRUE(w.on_bridge()) << w.x_m();
        }
      }));
  EXPECT_LT(off_at, 70);
  EXPECT_GT(off_at, 70 - 5 * kDt - 1e-9);
  EXPECT_FALSE(v.on_bridge());
  EXPECT_DOUBLE_EQ(v.elevation_m(), kGroundM);

  // Driving on forward, then backing off the way it came.
  Vehicle w = TankOnSpan(t, 120);
  ASSERT_TRUE(w.Command(-5, 0).ok());
  off_at = -1;
  ASSERT_TRUE(DriveUntil(
      t, w, [](const Vehicle& u) { return u.x_m() < 40; },
      [&](const Vehicle& u, const TraversalReport& r) {
        EXPECT_NE(r.event, BridgeEvent::kFellOff);
        if (r.event == BridgeEvent::kDroveOff) off_at = u.x_m();
      }));
  EXPECT_LT(off_at, 70);
  EXPECT_GT(off_at, 70 - 5 * kDt - 1e-9);
  EXPECT_TRUE(w.alive());
}

TEST(Traversal, StopOnTheSpanAndTurnAcrossItStaysOn) {
  Terrain t = FlatTerrain();
  ASSERT_TRUE(t.Add(kBridgeId, EastBridge()).ok());
  Vehicle v = TankOnSpan(t, 120);
  // Turn in place at full rate, the last step exactly onto north.
  while (v.heading_rad() < kPi / 2 - 1e-12) {
    const double rate = std::min(TankType().max_turn_rate_rad_s, (kPi / 2 - v.heading_rad()) / kDt);
    ASSERT_TRUE(v.Command(0, rate).ok());
    auto r = DriveVehicle(t, v, kDt);
    ASSERT_TRUE(r.ok());
    EXPECT_EQ(r.value().event, BridgeEvent::kNone);
    EXPECT_TRUE(v.on_bridge());
    EXPECT_GT(v.elevation_m(), kGroundM + 6);
  }
  EXPECT_NEAR(v.heading_rad(), kPi / 2, 1e-12);
  EXPECT_TRUE(v.on_bridge());
  EXPECT_TRUE(v.alive());
  // Across the span the deck slopes along the vehicle's width: the left (west) side is lower.
  EXPECT_LT(v.roll_rad(), 0.0);
  EXPECT_NEAR(v.pitch_rad(), 0.0, 1e-9);
  const double west = ExpectedDeck(v.x_m() - TankType().width_m / 2);
  const double east = ExpectedDeck(v.x_m() + TankType().width_m / 2);
  EXPECT_NEAR(v.roll_rad(), std::atan2(west - east, TankType().width_m), 1e-9);
}

TEST(Traversal, TurnAroundOnTheSpanAndDriveOffTheWayItCame) {
  Terrain t = FlatTerrain();
  ASSERT_TRUE(t.Add(kBridgeId, EastBridge()).ok());
  Vehicle v = TankOnSpan(t, 120);
  // The 10 m deck is wider than the tank's 8.7 m diagonal: a U-turn in place keeps all tires on.
  ASSERT_TRUE(v.Command(0, TankType().max_turn_rate_rad_s).ok());
  ASSERT_TRUE(DriveUntil(
      t, v, [](const Vehicle& w) { return w.heading_rad() < 0; },  // wrapped past pi
      [&](const Vehicle& w, const TraversalReport& r) {
        EXPECT_EQ(r.event, BridgeEvent::kNone);
        EXPECT_TRUE(w.on_bridge());
      }));
  ASSERT_TRUE(v.Command(0, 0).ok());
  // Facing about west now (heading just past pi); drive forward down ramp 1.
  ASSERT_TRUE(v.Command(5, 0).ok());
  double off_at = -1;
  ASSERT_TRUE(DriveUntil(
      t, v, [](const Vehicle& w) { return w.x_m() < 40; },
      [&](const Vehicle& w, const TraversalReport& r) {
        EXPECT_NE(r.event, BridgeEvent::kFellOff) << w.x_m();
        if (r.event == BridgeEvent::kDroveOff) off_at = w.x_m();
      }));
  EXPECT_LT(off_at, 70);
  EXPECT_GT(off_at, 62);
  EXPECT_TRUE(v.alive());
  EXPECT_DOUBLE_EQ(v.elevation_m(), kGroundM);
}

TEST(Traversal, VehicleUnderTheBridgeNeverJumpsToTheDeck) {
  Terrain t = FlatTerrain();
  ASSERT_TRUE(t.Add(kBridgeId, EastBridge()).ok());
  // Under the span and under the high end of ramp 1, crossing the bridge at right angles.
  for (double x : {120.0, 92.0}) {
    Vehicle v = Place(t, TankType(), x, 120, kPi / 2);
    ASSERT_TRUE(v.Command(6, 0).ok());
    int under = 0;
    ASSERT_TRUE(DriveUntil(
        t, v, [](const Vehicle& w) { return w.z_m() > 180; },
        [&](const Vehicle& w, const TraversalReport& r) {
          EXPECT_FALSE(w.on_bridge()) << w.z_m();
          EXPECT_EQ(r.event, BridgeEvent::kNone);
          EXPECT_DOUBLE_EQ(w.elevation_m(), kGroundM) << x << "," << w.z_m();
          EXPECT_DOUBLE_EQ(w.pitch_rad(), 0.0);
          if (BridgeOf(t).OverDeck(w.x_m(), w.z_m())) ++under;
        }));
    EXPECT_GT(under, 10) << x;
  }
  // Under the span heading along it (aligned, but not in a hot spot): still under.
  Vehicle along = Place(t, TankType(), 110, 150, 0.0);
  ASSERT_TRUE(along.Command(5, 0).ok());
  ASSERT_TRUE(DriveUntil(
      t, along, [](const Vehicle& w) { return w.x_m() > 130; },
      [&](const Vehicle& w, const TraversalReport&) {
        EXPECT_FALSE(w.on_bridge());
        EXPECT_DOUBLE_EQ(w.elevation_m(), kGroundM);
      }));
}

TEST(Traversal, EnteringAHotSpotAtRightAnglesCrossesTheRampEndLikeABerm) {
  Terrain t = FlatTerrain();
  ASSERT_TRUE(t.Add(kBridgeId, EastBridge()).ok());
  // Heading north across hot spot 1 where ramp 1 rises (x = 74: 0.8 m up the ramp).
  Vehicle v = Place(t, TankType(), 74, 125, kPi / 2);
  ASSERT_TRUE(v.Command(5, 0).ok());
  double highest = 0;
  ASSERT_TRUE(DriveUntil(
      t, v, [](const Vehicle& w) { return w.z_m() > 175; },
      [&](const Vehicle& w, const TraversalReport& r) {
        EXPECT_FALSE(w.on_bridge()) << w.z_m();
        EXPECT_NE(r.event, BridgeEvent::kMounted);
        highest = std::max(highest, w.elevation_m());
        // Fully on the ramp end (all points inside the hot spot): above the ground, and no
        // higher than the deck under its east (higher) side.
        if (w.z_m() - TankType().length_m / 2 >= 145 && w.z_m() + TankType().length_m / 2 <= 155) {
          EXPECT_NEAR(w.elevation_m(),
                      ExpectedDeck(74 + TankType().width_m / 2) -
                          TankType().width_m / 2 * std::tan(-w.roll_rad()),
                      1e-9);
          EXPECT_LT(w.roll_rad(), 0.0);  // east side (right, heading north) is higher
        }
        if (w.z_m() > 155 + TankType().length_m / 2) {
          EXPECT_DOUBLE_EQ(w.elevation_m(), kGroundM);
        }
      }));
  EXPECT_GT(highest, kGroundM + 0.5);
  // 30 degrees off the bridge direction: not aligned either.
  Vehicle skew = Place(t, TankType(), 50, 150 - 20 * std::tan(kPi / 6), kPi / 6);
  ASSERT_TRUE(skew.Command(5, 0).ok());
  ASSERT_TRUE(DriveUntil(
      t, skew, [](const Vehicle& w) { return w.x_m() > 75; },
      [&](const Vehicle& w, const TraversalReport&) { EXPECT_FALSE(w.on_bridge()) << w.x_m(); }));
  // 15 degrees off: aligned within the 20-degree tolerance, so it mounts.
  Vehicle near = Place(t, TankType(), 50, 150 - 20 * std::tan(kPi / 12), kPi / 12);
  ASSERT_TRUE(near.Command(5, 0).ok());
  ASSERT_TRUE(DriveUntil(
      t, near, [](const Vehicle& w) { return w.on_bridge(); }, {}, 10));
}

TEST(Traversal, TwoTiresOffFallsDyingPastTheLimitAndLivingBelowIt) {
  for (double height : {6.0, 0.5}) {
    Terrain t = FlatTerrain();
    ASSERT_TRUE(t.Add(kBridgeId, EastBridge(height, height)).ok());
    const Bridge& b = BridgeOf(t);
    Vehicle v = TankOnSpan(t, 120);
    // Turn a little left of north and drive off the north side: the front-left tire leaves
    // first (the vehicle stays on), then the front-right (it falls).
    ASSERT_TRUE(v.Command(0, 0.7).ok());
    ASSERT_TRUE(
        DriveUntil(t, v, [](const Vehicle& w) { return w.heading_rad() >= kPi / 2 + 0.1; }));
    ASSERT_TRUE(v.Command(2, 0).ok());
    int one_off = 0;
    TraversalReport fall;
    bool fell = false;
    for (int i = 0; i < 400 && !fell; ++i) {
      ASSERT_TRUE(v.Step(kDt).ok());
      const int off = UncarriedCorners(b, v);
      auto r = SettleVehicle(t, v);
      ASSERT_TRUE(r.ok());
      if (off == 1) {
        ++one_off;
        EXPECT_TRUE(v.on_bridge());
        EXPECT_EQ(r.value().event, BridgeEvent::kNone);
      }
      if (off >= 2) {
        fell = true;
        fall = r.value();
      }
    }
    ASSERT_TRUE(fell) << height;
    EXPECT_GT(one_off, 0);
    EXPECT_EQ(fall.event, BridgeEvent::kFellOff);
    EXPECT_FALSE(v.on_bridge());
    // Front corners on the ground, rear corners on the deck: nose down by about atan(h / L).
    EXPECT_LT(fall.fall_pitch_rad, -0.5 * std::atan2(height, TankType().length_m));
    const bool beyond = std::abs(fall.fall_pitch_rad) > TankType().max_pitch_rad ||
                        std::abs(fall.fall_roll_rad) > TankType().max_roll_rad;
    EXPECT_EQ(beyond, height > 1.0);
    EXPECT_EQ(fall.died, beyond);
    EXPECT_EQ(v.alive(), !beyond) << height;
    // It now stands on the ground beside the bridge.
    EXPECT_NEAR(v.elevation_m(), kGroundM, 1e-9);
    if (!beyond) {
      // The survivor drives on along the ground and never gets back on the deck.
      ASSERT_TRUE(v.Command(3, 0).ok());
      ASSERT_TRUE(DriveUntil(
          t, v, [](const Vehicle& w) { return w.z_m() > 170; },
          [](const Vehicle& w, const TraversalReport&) { EXPECT_FALSE(w.on_bridge()); }));
    } else {
      EXPECT_FALSE(v.Command(3, 0).ok());
    }
  }
}

TEST(Traversal, DestroyedSpanCannotBeCrossed) {
  Terrain t = FlatTerrain();
  FeatureParams p = EastBridge(10, 10);
  p.status = BridgeStatus::kDestroyed;
  ASSERT_TRUE(t.Add(kBridgeId, p).ok());
  Vehicle v = Place(t, TankType(), 50, 150, 0.0);
  ASSERT_TRUE(v.Command(5, 0).ok());
  TraversalReport fall;
  double fell_at = -1;
  DriveUntil(
      t, v, [](const Vehicle& w) { return !w.alive() || w.x_m() > 200; },
      [&](const Vehicle& w, const TraversalReport& r) {
        if (r.event == BridgeEvent::kFellOff) {
          fall = r;
          fell_at = w.x_m();
        }
        // Never on the deck beyond the broken joint.
        if (w.x_m() - TankType().length_m / 2 > 100) {
          EXPECT_FALSE(w.on_bridge());
        }
      });
  // It fell as its front tires passed the joint onto the broken span.
  EXPECT_NEAR(fell_at, 100 - TankType().length_m / 2, 5 * kDt + 1e-9);
  EXPECT_TRUE(fall.died);
  EXPECT_FALSE(v.alive());
  EXPECT_FALSE(v.on_bridge());
  EXPECT_LT(v.x_m(), 100);
  EXPECT_NEAR(v.elevation_m(), kGroundM, 1e-9);

  // Repaired, the same drive crosses the span on the deck.
  p.status = BridgeStatus::kIntact;
  ASSERT_TRUE(t.Update(kBridgeId, p).ok());
  Vehicle w = Place(t, TankType(), 50, 150, 0.0);
  ASSERT_TRUE(w.Command(5, 0).ok());
  ASSERT_TRUE(DriveUntil(t, w, [](const Vehicle& u) { return u.x_m() >= 120; }));
  EXPECT_TRUE(w.on_bridge());
  EXPECT_NEAR(w.elevation_m(), ExpectedDeck(w.x_m(), 10, 10), 1e-9);
}

TEST(Traversal, BridgeDestroyedOrRemovedUnderAVehicleDropsIt) {
  Terrain t = FlatTerrain();
  ASSERT_TRUE(t.Add(kBridgeId, EastBridge()).ok());
  Vehicle v = TankOnSpan(t, 120);
  FeatureParams p = EastBridge();
  p.status = BridgeStatus::kDestroyed;
  ASSERT_TRUE(t.Update(kBridgeId, p).ok());
  auto r = SettleVehicle(t, v);
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(r.value().event, BridgeEvent::kFellOff);
  EXPECT_FALSE(v.on_bridge());
  EXPECT_DOUBLE_EQ(v.elevation_m(), kGroundM);

  Terrain t2 = FlatTerrain();
  ASSERT_TRUE(t2.Add(kBridgeId, EastBridge()).ok());
  Vehicle w = TankOnSpan(t2, 120);
  ASSERT_TRUE(t2.Remove(kBridgeId).ok());
  r = SettleVehicle(t2, w);
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(r.value().event, BridgeEvent::kFellOff);
  EXPECT_FALSE(w.on_bridge());
  EXPECT_DOUBLE_EQ(w.elevation_m(), kGroundM);
}

TEST(Traversal, BadInputIsRefusedWithoutChanges) {
  Terrain t = FlatTerrain();
  auto other_size = Vehicle::Make(TankType(), 50, 50, 0, 100, 100);
  ASSERT_TRUE(other_size.ok());
  Vehicle v = std::move(other_size).value();
  auto r = SettleVehicle(t, v);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("terrain of 100 m"), std::string::npos) << r.error().message;
  ASSERT_TRUE(v.Command(5, 0).ok());
  EXPECT_FALSE(DriveVehicle(t, v, 1.0).ok());
  EXPECT_DOUBLE_EQ(v.x_m(), 50);  // not moved
  Vehicle w = Place(t, TankType(), 50, 50, 0);
  EXPECT_FALSE(DriveVehicle(t, w, std::numeric_limits<double>::quiet_NaN()).ok());
  EXPECT_FALSE(DriveVehicle(t, w, -1).ok());
}

constexpr float kDitchGroundM = 3.0f;
constexpr FeatureId kDitchId{1, 1, 1};

// The light (thesis) vehicle model drives on the composed surface: a tank driving along a tank
// ditch's floor rides the floor, six-point, whatever its length.
TEST(Vehicles, ALightTankDrivesDownADitchAndOutOfIt) {
  Terrain t(HeightGrid(201, 1.0, kDitchGroundM, Material::kGrass));
  ASSERT_TRUE(
      t.Add(kDitchId, FeatureParams::Ditch({{40, 100, 2.5, 12}, {160, 100, 2.5, 12}}, 3.0)).ok());
  auto made =
      Vehicle::Make(TankType(), 100, 100, 0.0, t.ground().size_x_m(), t.ground().size_z_m());
  ASSERT_TRUE(made.ok());
  Vehicle tank = made.value();
  auto settled = SettleVehicle(t, tank);
  ASSERT_TRUE(settled.ok()) << settled.error().message;
  EXPECT_EQ(settled.value().method, OrientationMethod::kSixPoint);
  EXPECT_NEAR(tank.elevation_m(), kDitchGroundM - 2.5, 1e-9);  // on the 6 m floor
  // Turned across the ditch, the tank's ends reach up its sides: it sits higher than the floor.
  made = Vehicle::Make(TankType(), 100, 100, std::numbers::pi / 2, t.ground().size_x_m(),
                       t.ground().size_z_m());
  ASSERT_TRUE(made.ok());
  Vehicle across = made.value();
  ASSERT_TRUE(SettleVehicle(t, across).ok());
  EXPECT_GT(across.elevation_m(), kDitchGroundM - 2.5);
}

}  // namespace
}  // namespace dt
