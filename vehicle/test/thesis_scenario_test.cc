// Thesis chapter IV vehicle behaviours as named scenarios: each prints its figures and checks
// them, under the physical model and, where the thesis's rule applies, the light model.
#include <cstdio>
#include <utility>

#include "terrain/berm.h"
#include "terrain/berm_operations.h"
#include "terrain/bridge.h"
#include "vehicle/light_vehicle.h"
#include "vehicle/test/vehicle_fixtures.h"
#include "vehicle/vehicle_traversal.h"

namespace dt::test {
namespace {

constexpr FeatureId kBridge{1, 1, 1};
constexpr double kPi = 3.14159265358979323846;

// A 6 m bridge on flat ground at 10 m: ramp 1 from x 70 to 100, span to 140, ramp 2 to 170, at
// z = 200, 10 m wide (deck 16 m at the span).
std::unique_ptr<Terrain> BridgeTerrain(double height_m = 6.0, bool destroyed = false) {
  auto t = FlatTerrain();
  FeatureParams p = FeatureParams::Bridge(100, 200, 0.0, 10, 30, 40, 30, height_m, height_m);
  if (destroyed) p.status = BridgeStatus::kDestroyed;
  EXPECT_TRUE(t->Add(kBridge, p).ok());
  return t;
}

// The deepest any point of the hull's bottom lies below the ground and earthworks.
double GroundPenetration(const Terrain& t, const PhysicalVehicle& v) {
  double worst = 0.0;
  for (const Eigen::Vector3d& p : v.HullBottomPoints(0.25)) {
    worst = std::max(worst, t.ElevationAt(p.x(), p.z()) - p.y());
  }
  return worst;
}

void Print(const char* scenario, const PhysicalVehicle& v, const DriveLog& l) {
  std::printf(
      "%s [physical %s]: end x %.1f z %.1f elevation %.2f m, speed %.2f m/s; pitch %.1f..%.1f "
      "deg, roll %.1f..%.1f deg, elevation %.2f..%.2f m; landing %.2f m/s; events mounted %d "
      "drove-off %d fell-off %d; blocked %d ticks; damage %s %s\n",
      scenario, v.type().base.name.c_str(), v.x_m(), v.z_m(), v.elevation_m(), v.speed_mps(),
      Deg(l.min_pitch_rad), Deg(l.max_pitch_rad), Deg(l.min_roll_rad), Deg(l.max_roll_rad),
      l.min_elevation_m, l.max_elevation_m, l.max_landing_mps, l.mounted, l.drove_off, l.fell_off,
      l.blocked_ticks, std::string(DamageName(v.damage())).c_str(), l.cause.c_str());
}

// The light model driven the same way; records tilt extremes and events.
struct LightLog {
  double max_pitch_rad = -INFINITY, min_pitch_rad = INFINITY;
  double max_roll_rad = -INFINITY, min_roll_rad = INFINITY, max_elevation_m = -INFINITY;
  int mounted = 0, drove_off = 0, fell_off = 0;
  double first_pitch_rad = 0.0;  // sign of the first tilt over 2 deg
};
template <typename Stop>
LightLog DriveLight(const Terrain& t, LightVehicle& v, double speed, double rate, double seconds,
                    Stop stop) {
  LightLog log;
  EXPECT_TRUE(v.Command(speed, rate).ok());
  for (int i = 0; i < static_cast<int>(seconds * 30) && !stop(v.vehicle()); ++i) {
    const LightReport r = v.Advance(t, kTick).value();
    const Vehicle& k = v.vehicle();
    log.max_pitch_rad = std::max(log.max_pitch_rad, k.pitch_rad());
    log.min_pitch_rad = std::min(log.min_pitch_rad, k.pitch_rad());
    log.max_roll_rad = std::max(log.max_roll_rad, k.roll_rad());
    log.min_roll_rad = std::min(log.min_roll_rad, k.roll_rad());
    log.max_elevation_m = std::max(log.max_elevation_m, k.elevation_m());
    if (log.first_pitch_rad == 0.0 && std::abs(k.pitch_rad()) > 2.0 * kPi / 180) {
      log.first_pitch_rad = k.pitch_rad();
    }
    log.mounted += r.event == BridgeEvent::kMounted;
    log.drove_off += r.event == BridgeEvent::kDroveOff;
    log.fell_off += r.event == BridgeEvent::kFellOff;
  }
  return log;
}
LightLog DriveLight(const Terrain& t, LightVehicle& v, double speed, double rate, double seconds) {
  return DriveLight(t, v, speed, rate, seconds, [](const Vehicle&) { return false; });
}
void PrintLight(const char* scenario, const LightVehicle& v, const LightLog& l) {
  const Vehicle& k = v.vehicle();
  std::printf(
      "%s [light tank]: end x %.1f z %.1f elevation %.2f m; pitch %.1f..%.1f deg, roll "
      "%.1f..%.1f deg; events mounted %d drove-off %d fell-off %d; alive %d\n",
      scenario, k.x_m(), k.z_m(), k.elevation_m(), Deg(l.min_pitch_rad), Deg(l.max_pitch_rad),
      Deg(l.min_roll_rad), Deg(l.max_roll_rad), l.mounted, l.drove_off, l.fell_off, k.alive());
}

TEST(ThesisScenario, CraterOnOneTrack) {
  auto t = FlatTerrain();
  ASSERT_TRUE(
      t->Add({1, 1, 9}, FeatureParams::Crater(100, 100, 10)).ok());  // rim 1.5 m, 6..8 m out
  // Heading east with the left (north) track over the rim's middle, 7 m from the centre; the
  // right track passes outside the crater.
  auto v = PhysicalVehicle::Make(PhysType("tank"), *t, 70, 93 - 1.85, 0).value();
  double worst = 0.0;
  const DriveLog l = Drive(*t, v, 4, 0, 20, [&](const PhysicalVehicle& pv) {
    worst = std::max(worst, GroundPenetration(*t, pv));
    return pv.x_m() > 125;
  });
  Print("crater on one track", v, l);
  std::printf("  deepest hull penetration %.3f m\n", worst);
  // Left side up is right side down: positive roll, about atan(1.5 / 3.7) = 22 deg.
  EXPECT_GT(Deg(l.max_roll_rad), 15.0);
  EXPECT_LT(Deg(l.max_roll_rad), 35.0);
  EXPECT_GT(v.x_m(), 125.0);
  EXPECT_TRUE(v.mobile());
  EXPECT_LT(worst, 0.1);

  auto k = LightVehicle::Make(TankType(), *t, 70, 93 - 1.85, 0).value();
  const LightLog ll = DriveLight(*t, k, 4, 0, 20, [](const Vehicle& kv) { return kv.x_m() > 125; });
  PrintLight("crater on one track", k, ll);
  EXPECT_GT(Deg(ll.max_roll_rad), 15.0);
}

TEST(ThesisScenario, BermHeadOnAndReversing) {
  auto t = FlatTerrain();
  // A berm 1 m high, 6 m wide at the base (2 m slopes, 27 deg), crest along z at x = 100.
  ASSERT_TRUE(t->Add({1, 1, 9}, FeatureParams::Berm(100, 150, kPi / 2, 40, 6, 1.0)).ok());
  auto v = PhysicalVehicle::Make(PhysType("tank"), *t, 80, 170, 0).value();
  double worst = 0.0, first_pitch = 0.0;
  auto watch = [&](const PhysicalVehicle& pv) {
    worst = std::max(worst, GroundPenetration(*t, pv));
    if (first_pitch == 0.0 && std::abs(pv.pitch_rad()) > 2.0 * kPi / 180)
      first_pitch = pv.pitch_rad();
    return false;
  };
  DriveLog l = Drive(*t, v, 4, 0, 12, watch);
  Print("berm head-on", v, l);
  std::printf("  first tilt %.1f deg, deepest hull penetration %.3f m\n", Deg(first_pitch), worst);
  EXPECT_GT(v.x_m(), 110.0);            // over it
  EXPECT_GT(first_pitch, 0.0);          // nose up first
  EXPECT_LT(l.min_pitch_rad, -0.05);    // then down
  EXPECT_LT(worst, 0.1);                // never 1.2 m inside the hull
  EXPECT_LT(Deg(l.max_pitch_rad), 30);  // never balanced on one end with the other in the air

  first_pitch = 0.0;
  worst = 0.0;
  l = Drive(*t, v, -4, 0, 15, [&](const PhysicalVehicle& pv) {
    watch(pv);
    return pv.x_m() < 85;
  });
  Print("berm reversing", v, l);
  std::printf("  first tilt %.1f deg, deepest hull penetration %.3f m\n", Deg(first_pitch), worst);
  EXPECT_LT(v.x_m(), 90.0);
  EXPECT_LT(first_pitch, 0.0);  // the rear climbs first: nose down
  EXPECT_LT(worst, 0.1);

  // A 3 m berm with 56-degree faces is steeper than any grip: the tank stops against it.
  auto steep = FlatTerrain();
  ASSERT_TRUE(steep->Add({1, 1, 9}, FeatureParams::Berm(100, 150, kPi / 2, 40, 6, 3.0)).ok());
  auto s = PhysicalVehicle::Make(PhysType("tank"), *steep, 80, 170, 0).value();
  l = Drive(*steep, s, 4, 0, 15);
  Print("steep berm head-on", s, l);
  EXPECT_LT(s.x_m(), 97.0);
  EXPECT_LT(l.max_elevation_m, 12.0);

  auto k = LightVehicle::Make(TankType(), *t, 80, 170, 0).value();
  LightLog ll = DriveLight(*t, k, 4, 0, 12);
  PrintLight("berm head-on", k, ll);
  EXPECT_GT(ll.first_pitch_rad, 0.0);
  ll = DriveLight(*t, k, -4, 0, 12, [](const Vehicle& kv) { return kv.x_m() < 85; });
  PrintLight("berm reversing", k, ll);
  EXPECT_LT(ll.first_pitch_rad, 0.0);
}

TEST(ThesisScenario, BridgeGetOnAlignedGoesOverAndOff) {
  auto t = BridgeTerrain();
  auto v = PhysicalVehicle::Make(PhysType("tank"), *t, 50, 200, 0).value();
  const DriveLog l =
      Drive(*t, v, 8, 0, 25, [](const PhysicalVehicle& pv) { return pv.x_m() > 190; });
  Print("bridge aligned, over", v, l);
  EXPECT_EQ(l.mounted, 1);
  EXPECT_EQ(l.drove_off, 1);
  EXPECT_EQ(l.fell_off, 0);
  EXPECT_NEAR(l.max_elevation_m, 16.0, 0.1);
  EXPECT_GT(v.x_m(), 190.0);
  EXPECT_TRUE(v.mobile());

  auto k = LightVehicle::Make(TankType(), *t, 50, 200, 0).value();
  const LightLog ll = DriveLight(*t, k, 8, 0, 25, [](const Vehicle& kv) { return kv.x_m() > 190; });
  PrintLight("bridge aligned, over", k, ll);
  EXPECT_EQ(ll.mounted, 1);
  EXPECT_EQ(ll.drove_off, 1);
  EXPECT_NEAR(ll.max_elevation_m, 16.0, 0.1);
}

TEST(ThesisScenario, BridgeGetOnMisalignedDoesNotReachTheSpan) {
  auto t = BridgeTerrain();
  // 45 degrees off the bridge, aimed at the side of ramp 1 half-way up (deck 3 m there).
  auto v = PhysicalVehicle::Make(PhysType("tank"), *t, 70, 180, kPi / 4).value();
  const DriveLog l = Drive(*t, v, 5, 0, 15);
  Print("bridge misaligned", v, l);
  EXPECT_LT(l.max_elevation_m, 12.0);  // never up on the deck
  EXPECT_GT(l.blocked_ticks, 0);       // stopped by the ramp's side
  EXPECT_LT(v.z_m(), 196.0);

  auto k = LightVehicle::Make(TankType(), *t, 70, 180, kPi / 4).value();
  const LightLog ll = DriveLight(*t, k, 5, 0, 15);
  PrintLight("bridge misaligned", k, ll);
  EXPECT_EQ(ll.mounted, 0);
}

TEST(ThesisScenario, UnderTheSpanOnlyWhereTheHullFits) {
  // Under a 6 m span (underside 5.5 m above the ground) a 2.4 m tank passes across.
  auto t = BridgeTerrain();
  auto v = PhysicalVehicle::Make(PhysType("tank"), *t, 120, 180, kPi / 2).value();
  DriveLog l = Drive(*t, v, 6, 0, 8);
  Print("under a 6 m span", v, l);
  EXPECT_GT(v.z_m(), 215.0);
  EXPECT_EQ(l.blocked_ticks, 0);
  EXPECT_EQ(l.mounted, 0);
  EXPECT_NEAR(l.max_elevation_m, 10.0, 0.05);

  // Under a 2.5 m span (underside 2.0 m) it does not fit: it stops at the deck's edge.
  auto low = BridgeTerrain(2.5);
  auto w = PhysicalVehicle::Make(PhysType("tank"), *low, 120, 180, kPi / 2).value();
  l = Drive(*low, w, 6, 0, 8);
  Print("under a 2.5 m span", w, l);
  EXPECT_LT(w.z_m() + 7.9 / 2, 195.0 + 0.1);
  EXPECT_GT(l.blocked_ticks, 0);

  // Along the bridge under the span towards ramp 2, the ramp's underside comes down to the roof.
  auto x = PhysicalVehicle::Make(PhysType("tank"), *t, 125, 200, 0).value();
  l = Drive(*t, x, 6, 0, 10);
  Print("along under the span into ramp 2", x, l);
  EXPECT_LT(l.max_elevation_m, 10.1);  // never jumps up onto the ramp
  EXPECT_GT(l.blocked_ticks, 0);
  EXPECT_LT(x.x_m(), 160.0);
}

TEST(ThesisScenario, BackOffTheBridge) {
  auto t = BridgeTerrain();
  auto v = PhysicalVehicle::Make(PhysType("tank"), *t, 50, 200, 0).value();
  Drive(*t, v, 8, 0, 20, [](const PhysicalVehicle& pv) { return pv.x_m() > 120; });
  ASSERT_TRUE(v.on_bridge());
  const DriveLog l =
      Drive(*t, v, -5, 0, 30, [](const PhysicalVehicle& pv) { return pv.x_m() < 50; });
  Print("back off", v, l);
  EXPECT_EQ(l.drove_off, 1);
  EXPECT_EQ(l.fell_off, 0);
  EXPECT_FALSE(v.on_bridge());
  EXPECT_NEAR(v.elevation_m(), 10.0, 0.05);
  EXPECT_TRUE(v.mobile());
}

TEST(ThesisScenario, FallOffTheSideDiesFromSixMetresNotFromOne) {
  for (const double height : {6.0, 1.0}) {
    auto t = BridgeTerrain(height);
    auto v = PhysicalVehicle::Make(PhysType("tank"), *t, 50, 200, 0).value();
    Drive(*t, v, 8, 0, 20, [](const PhysicalVehicle& pv) { return pv.x_m() > 115; });
    ASSERT_TRUE(v.on_bridge());
    const DriveLog l = Drive(*t, v, 5, 0.4, 10);
    Print(height == 6.0 ? "fall off a 6 m span (die)" : "fall off a 1 m span", v, l);
    EXPECT_EQ(l.fell_off, 1);  // once, not once per tick
    EXPECT_FALSE(v.on_bridge());
    EXPECT_NEAR(v.elevation_m(), 10.0, 0.2);
    if (height == 6.0) {
      EXPECT_EQ(v.damage(), Damage::kDestroyed);
      EXPECT_GT(l.max_landing_mps, PhysType("tank").land_kill_mps);
    } else {
      EXPECT_EQ(v.damage(), Damage::kNone);
    }
  }
}

TEST(ThesisScenario, DestroyedBridgeIsImpassableAtAnyHeight) {
  auto t = BridgeTerrain(6.0, true);
  // On the deck: ramp 1 ends in a drop at the break; the fall kills.
  auto v = PhysicalVehicle::Make(PhysType("tank"), *t, 50, 200, 0).value();
  DriveLog l = Drive(*t, v, 8, 0, 30);
  Print("destroyed bridge, on the deck", v, l);
  EXPECT_EQ(l.mounted, 1);
  EXPECT_EQ(l.fell_off, 1);
  EXPECT_EQ(v.damage(), Damage::kDestroyed);
  EXPECT_LT(v.x_m(), 140.0);  // never out at the far side
  // Below: the fallen span lies in the way.
  auto w = PhysicalVehicle::Make(PhysType("tank"), *t, 120, 180, kPi / 2).value();
  l = Drive(*t, w, 6, 0, 8);
  Print("destroyed bridge, from below", w, l);
  EXPECT_GT(l.blocked_ticks, 0);
  EXPECT_LT(w.z_m(), 195.0);
  // A low destroyed bridge (2 m: a 1.5 m drop onto the rubble) is survived, and still not
  // crossed: ramp 2 is out of reach above the rubble.
  auto low = BridgeTerrain(2.0, true);
  auto s = PhysicalVehicle::Make(PhysType("tank"), *low, 50, 200, 0).value();
  l = Drive(*low, s, 6, 0, 40);
  Print("low destroyed bridge", s, l);
  EXPECT_TRUE(s.alive());
  EXPECT_LT(s.x_m(), 150.0);
}

TEST(ThesisScenario, RampSideStopsAVehicleWhereItIsHigherThanTheBelly) {
  // Ramp 1 at x = 80 (along -20): deck 2 m, underside 1.5 m: a side the tank cannot pass.
  auto t = BridgeTerrain();
  auto v = PhysicalVehicle::Make(PhysType("tank"), *t, 80, 180, kPi / 2).value();
  const DriveLog l = Drive(*t, v, 8, 0, 6);
  Print("across ramp 1 at 2 m", v, l);
  EXPECT_GT(l.blocked_ticks, 0);
  EXPECT_LT(v.z_m() + 7.9 / 2, 195.1);
}

// Thesis IV: a vehicle turning on the span stays on the deck (the tag holds, no fall), with the
// deck under all its running gear.
TEST(ThesisScenario, TurningOnTheSpanStaysOnTheDeck) {
  auto t = BridgeTerrain();
  auto v = PhysicalVehicle::Make(PhysType("tank"), *t, 50, 200, 0).value();
  Drive(*t, v, 8, 0, 20, [](const PhysicalVehicle& pv) { return pv.x_m() > 118; });
  Drive(*t, v, 0, 0, 3);  // brake to a stop on the span
  ASSERT_TRUE(v.on_bridge());
  const double heading0 = v.heading_rad();
  const DriveLog l = Drive(*t, v, 0, 0.5, 10, [&](const PhysicalVehicle& pv) {
    return pv.heading_rad() - heading0 >= kPi / 2;
  });
  Print("turn on the span", v, l);
  std::printf("  turned %.1f deg on the spot\n", Deg(v.heading_rad() - heading0));
  EXPECT_GE(v.heading_rad() - heading0, kPi / 2 - 0.02);
  EXPECT_TRUE(v.on_bridge());
  EXPECT_EQ(l.fell_off + l.drove_off + l.mounted, 0);
  EXPECT_NEAR(l.min_elevation_m, 16.0, 0.05);  // on the deck throughout
  EXPECT_NEAR(l.max_elevation_m, 16.0, 0.05);
  EXPECT_LT(std::max(Deg(l.max_roll_rad), -Deg(l.min_roll_rad)), 1.0);
  EXPECT_TRUE(v.mobile());
}

// Thesis IV, one tire off the deck: a jeep on the span with its centre of mass past the edge
// (its right wheels off the deck, its left wheels on it) tips off and falls: one fell-off event,
// and it ends on the ground below, destroyed. (With the centre of mass over the deck it stays:
// OneTireOffTheDeckWithTheCentreOverItRests.)
TEST(ThesisScenario, OneTireOffTheDeckWithTheCentrePastTheEdgeFalls) {
  auto t = BridgeTerrain();
  // The deck spans z 195..205; heading +x, the jeep's right side is towards -z.
  auto v = PhysicalVehicle::MakeAt(PhysType("jeep"), *t, 120, 194.6, 0, 16.0).value();
  const DriveLog l = Drive(*t, v, 0, 0, 5);
  Print("one tire off, centre past the edge", v, l);
  EXPECT_EQ(l.mounted, 1);  // its left wheels stood on the deck
  EXPECT_EQ(l.fell_off, 1);
  EXPECT_FALSE(v.on_bridge());
  EXPECT_GT(l.max_roll_rad, 0.5);  // over to the right first
  // On the ground below (10 m) as a wreck on its side or roof: the running gear's bottom no
  // higher than the hull is tall above it, with some slack for a wreck lying on a pier's rubble.
  EXPECT_LT(v.elevation_m(), 10.0 + PhysType("jeep").hull_height_m + 0.5);
  EXPECT_EQ(v.damage(), Damage::kDestroyed);
}

// Thesis IV and fig. 7, emplacement: a tank reverses into a U of three berms open to the rear
// and stops inside it, hull out of the berms, level between the side berms.
TEST(ThesisScenario, EmplacementBackedInto) {
  auto t = FlatTerrain();
  EmplacementSpec spec;
  spec.centre_x_m = 150;
  spec.centre_z_m = 150;
  spec.facing_rad = 0.0;  // front berm at x 156, open towards -x
  spec.size_m = 12;
  spec.width_m = 4;
  spec.height_m = 2;
  const auto berms = EmplacementBerms(spec).value();
  for (uint32_t k = 0; k < 3; ++k) ASSERT_TRUE(t->Add({1, 1, 20 + k}, berms[k]).ok());
  // Facing away from the front berm, backing in from outside the opening.
  auto v = PhysicalVehicle::Make(PhysType("tank"), *t, 128, 150, kPi).value();
  double worst = 0.0;
  const DriveLog l = Drive(*t, v, -3, 0, 20, [&](const PhysicalVehicle& pv) {
    worst = std::max(worst, GroundPenetration(*t, pv));
    return pv.x_m() > 149;
  });
  const DriveLog rest = Drive(*t, v, 0, 0, 3);
  Print("emplacement, backed in", v, l);
  std::printf("  at rest x %.1f z %.1f, roll %.1f deg, deepest hull penetration %.3f m\n", v.x_m(),
              v.z_m(), Deg(v.roll_rad()), worst);
  EXPECT_GT(v.x_m(), 148.0);  // inside the U: its centre past the side berms' open ends
  EXPECT_LT(v.x_m(), 152.0);  // short of the front berm's foot (x 154)
  EXPECT_NEAR(v.z_m(), 150.0, 0.5);
  EXPECT_LT(worst, 0.1);
  EXPECT_LT(std::max(Deg(l.max_roll_rad), -Deg(l.min_roll_rad)), 1.0);  // never on a side berm
  EXPECT_NEAR(rest.max_elevation_m, 10.0, 0.05);                        // on the pit's floor
  EXPECT_TRUE(v.mobile());
}

// Thesis III.C.2 and IV, breach: a berm too steep to climb stops a tank; a gap cut through it
// while the tank waits (the terrain changes under a vehicle that keeps what it gathered) lets it
// drive through on the ground.
TEST(ThesisScenario, BreachLetsATankThroughABermThatStoppedIt) {
  auto t = FlatTerrain();
  const FeatureId berm{1, 1, 9};
  // 3 m high, 6 m wide: 56-degree faces, crest along z at x = 100 from z 130 to 170.
  ASSERT_TRUE(t->Add(berm, FeatureParams::Berm(100, 130, kPi / 2, 40, 6, 3.0)).ok());
  auto v = PhysicalVehicle::Make(PhysType("tank"), *t, 80, 150, 0).value();
  DriveLog l = Drive(*t, v, 4, 0, 10);
  Print("berm before the breach", v, l);
  EXPECT_LT(v.x_m(), 97.0);
  EXPECT_LT(l.max_elevation_m, 12.0);
  const double stopped_x = v.x_m();
  // Back off the berm's foot onto the flat ground and wait there.
  Drive(*t, v, -3, 0, 10, [](const PhysicalVehicle& pv) { return pv.x_m() < 85; });
  Drive(*t, v, 0, 0, 2);
  ASSERT_NEAR(v.elevation_m(), 10.0, 0.01);

  const auto* b = static_cast<const Berm*>(t->Find(berm));
  const auto pieces = BreachBerm(*b, 20.0, 8.0).value();  // an 8 m gap at z 146..154
  ASSERT_TRUE(t->Remove(berm).ok());
  for (uint32_t k = 0; k < pieces.size(); ++k) ASSERT_TRUE(t->Add({1, 1, 30 + k}, pieces[k]).ok());
  double worst = 0.0;
  l = Drive(*t, v, 4, 0, 15, [&](const PhysicalVehicle& pv) {
    worst = std::max(worst, GroundPenetration(*t, pv));
    return pv.x_m() > 115;
  });
  Print("through the breach", v, l);
  std::printf("  stopped at x %.1f before; deepest hull penetration through the gap %.3f m\n",
              stopped_x, worst);
  EXPECT_GT(v.x_m(), 115.0);
  EXPECT_NEAR(v.z_m(), 150.0, 0.5);
  EXPECT_LT(l.max_elevation_m, 10.1);  // on the ground through the gap
  EXPECT_LT(worst, 0.1);
  EXPECT_TRUE(v.mobile());
}

TEST(ThesisScenario, LightModelReportsAFallOnce) {
  // A tank in ramp 1's hot spot with its right side off the deck, creeping along the bridge: the
  // kinematic rules tag it and drop it again every tick.
  auto t = BridgeTerrain();
  Vehicle raw =
      Vehicle::Make(TankType(), 75, 196, 0, t->ground().size_x_m(), t->ground().size_z_m()).value();
  ASSERT_TRUE(raw.Command(0.2, 0).ok());
  int raw_falls = 0;
  for (int i = 0; i < 20; ++i)
    raw_falls += DriveVehicle(*t, raw, kTick).value().event == BridgeEvent::kFellOff;
  auto k = LightVehicle::Make(TankType(), *t, 75, 196, 0).value();
  const LightLog ll = DriveLight(*t, k, 0.2, 0, 20 * kTick);
  std::printf(
      "hanging in a hot spot for 20 ticks: SettleVehicle reports %d falls, the light model %d\n",
      raw_falls, ll.fell_off);
  EXPECT_GT(raw_falls, 1);
  EXPECT_EQ(ll.fell_off, 1);
  EXPECT_EQ(ll.mounted, 0);
}

// Thesis IV, one tire off with the centre over the deck: the jeep (2.2 m wide) with its right
// side 0.2 to 0.8 m past the edge (centre 0.9 to 0.3 m inside it) settles rolled onto its bottom
// at the edge and stays on the span, unharmed. At rest its left wheels stand on the deck and its
// belly on the edge, so the roll is atan((clearance - sag) / (distance from the left wheels to
// the edge)): 9.9 deg with the centre 0.9 m inside, 14.0 deg with it 0.3 m inside.
TEST(ThesisScenario, OneTireOffTheDeckWithTheCentreOverItRests) {
  const PhysicalVehicleType jeep = PhysType("jeep");
  for (const double z : {195.9, 195.7, 195.5, 195.3}) {
    auto t = BridgeTerrain();
    auto v = PhysicalVehicle::MakeAt(jeep, *t, 120, z, 0, 16.0).value();
    const DriveLog l = Drive(*t, v, 0, 0, 5);
    const double inside_m = z - 195.0;
    const double rest_roll_rad =
        std::atan((jeep.clearance_m - kStaticSagM) / (inside_m + jeep.base.width_m / 2.0));
    std::printf("centre %.1f m inside the edge: ", inside_m);
    Print("one tire off, centre over the deck", v, l);
    std::printf("  at rest roll %.1f deg (wheels and belly on the deck: %.1f deg)\n",
                Deg(v.roll_rad()), Deg(rest_roll_rad));
    EXPECT_EQ(l.fell_off, 0) << z;
    EXPECT_TRUE(v.on_bridge()) << z;
    EXPECT_EQ(v.damage(), Damage::kNone) << z;
    EXPECT_NEAR(v.roll_rad(), rest_roll_rad, 0.035) << z;  // 2 degrees
    EXPECT_LT(l.max_roll_rad, rest_roll_rad + 0.1) << z;   // the drop onto the edge overshoots
    EXPECT_NEAR(v.z_m(), z, 0.05) << z;                    // not pushed off sideways
  }
}

// Thesis IV.B.3: a vehicle leaves a bridge by driving off only through the outer part of a hot
// spot (beyond a ramp's foot, within the bridge's width); leaving anywhere else is a fall. A tank
// 30 degrees off the bridge's axis mounts ramp 1 at its foot and rolls off the ramp's side: at
// 8 m/s from z 176 it goes over the south side 11 m from the foot (reported as driving off while
// the rule looked only at where the deck last carried the gear), from z 180 over the north side.
TEST(ThesisScenario, LeavingARampsSideIsAFallNotDrivingOff) {
  for (const auto& [speed, z0] : {std::pair{8.0, 176.0}, {3.0, 180.0}, {5.0, 180.0}}) {
    auto t = BridgeTerrain();
    auto v = PhysicalVehicle::Make(PhysType("tank"), *t, 40, z0, kPi / 6).value();
    DriveLog l =
        Drive(*t, v, speed, 0, 20, [](const PhysicalVehicle& pv) { return pv.z_m() > 215; });
    const DriveLog rest = Drive(*t, v, 0, 0, 10);
    l.fell_off += rest.fell_off;
    l.drove_off += rest.drove_off;
    Print("30 deg off the axis, off ramp 1's side", v, l);
    EXPECT_EQ(l.mounted, 1) << speed << " m/s from z " << z0;
    EXPECT_EQ(l.drove_off, 0) << speed << " m/s from z " << z0;
    EXPECT_EQ(l.fell_off, 1) << speed << " m/s from z " << z0;
    EXPECT_EQ(v.damage(), Damage::kDestroyed);
    EXPECT_FALSE(v.on_bridge());
  }
}

}  // namespace
}  // namespace dt::test
