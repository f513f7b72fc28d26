#include "vehicle/test/vehicle_fixtures.h"
#include "terrain/bridge.h"
namespace dt::test {
void Show(const char* what, const PhysicalVehicle& v, const DriveLog& l) {
  std::printf("%-28s x %7.2f z %7.2f elev %6.2f head %5.2f speed %5.2f pitch %5.1f..%5.1f roll %5.1f..%5.1f elev %5.2f..%5.2f land %5.2f m%d d%d f%d blk %d slide %d dmg %s %s\n", what, v.x_m(), v.z_m(), v.elevation_m(), v.heading_rad(), v.speed_mps(), Deg(l.min_pitch_rad), Deg(l.max_pitch_rad), Deg(l.min_roll_rad), Deg(l.max_roll_rad), l.min_elevation_m, l.max_elevation_m, l.max_landing_mps, l.mounted, l.drove_off, l.fell_off, l.blocked_ticks, l.sliding_ticks, std::string(DamageName(v.damage())).c_str(), l.cause.c_str());
}
TEST(Probe, Bridges) {
  auto t = FlatTerrain();
  // span x 100..140 at z 200, ramps 30 m, 6 m high, 10 m wide.
  ASSERT_TRUE(t->Add({1, 1, 1}, FeatureParams::Bridge(100, 200, 0.0, 10, 30, 40, 30, 6, 6)).ok());
  ASSERT_TRUE(t->Add({1, 1, 2}, FeatureParams::Bridge(100, 300, 0.0, 10, 30, 40, 30, 6, 6)).ok());
  t->Update({1,1,2}, [&]{auto p = t->Find({1,1,2})->params(); p.status = BridgeStatus::kDestroyed; return p;}()).ok();
  ASSERT_TRUE(t->Add({1, 1, 3}, FeatureParams::Crater(100, 100, 10)).ok());
  { auto v = PhysicalVehicle::Make(PhysType("tank"), *t, 40, 200, 0).value(); auto l = Drive(*t, v, 8, 0, 30, [](auto& v){return v.x_m() > 210;}); Show("aligned over", v, l); }
  { auto v = PhysicalVehicle::Make(PhysType("tank"), *t, 40, 200, 0).value(); auto l = Drive(*t, v, 8, 0, 30, [](auto& v){return v.x_m() > 120;}); Show("to span", v, l); l = Drive(*t, v, -5, 0, 30, [](auto& v){return v.x_m() < 40;}); Show("back off", v, l);}
  { auto v = PhysicalVehicle::Make(PhysType("tank"), *t, 90, 170, 1.5708).value(); auto l = Drive(*t, v, 8, 0, 8); Show("across ramp (6m side)", v, l); }
  { auto v = PhysicalVehicle::Make(PhysType("tank"), *t, 120, 170, 1.5708).value(); auto l = Drive(*t, v, 8, 0, 8); Show("under span", v, l); }
  { auto v = PhysicalVehicle::Make(PhysType("tank"), *t, 40, 200, 0).value(); auto l = Drive(*t, v, 8, 0, 30, [](auto& v){return v.x_m() > 120;}); Show("to span", v, l); l = Drive(*t, v, 5, 0.3, 10); Show("off side", v, l);}
  { auto v = PhysicalVehicle::Make(PhysType("tank"), *t, 40, 300, 0).value(); auto l = Drive(*t, v, 8, 0, 30, [](auto& v){return v.x_m() > 210;}); Show("destroyed", v, l); }
  { auto v = PhysicalVehicle::Make(PhysType("tank"), *t, 120, 270, 1.5708).value(); auto l = Drive(*t, v, 8, 0, 8); Show("under destroyed", v, l); }
  { auto v = PhysicalVehicle::Make(PhysType("tank"), *t, 80, 96.3, 0).value(); auto l = Drive(*t, v, 5, 0, 8); Show("crater one track", v, l); }
  { auto v = PhysicalVehicle::Make(PhysType("tank"), *t, 60, 40, 0).value(); auto l = Drive(*t, v, 0, 0.5, 3); Show("turn", v, l); }
}
}
