#include "vehicle/test/vehicle_fixtures.h"
#include "terrain/bridge.h"
namespace dt::test {
TEST(Probe, LowFall) {
  auto t = FlatTerrain();
  ASSERT_TRUE(t->Add({1, 1, 1}, FeatureParams::Bridge(100, 200, 0.0, 10, 30, 40, 30, 1, 1)).ok());
  auto v = PhysicalVehicle::Make(PhysType("tank"), *t, 50, 200, 0).value();
  Drive(*t, v, 8, 0, 20, [](const PhysicalVehicle& pv) { return pv.x_m() > 115; });
  v.Command(5, 0.4).ok();
  for (int i = 0; i < 300; ++i) {
    auto r = v.Advance(*t, kTick).value();
    if (r.mounted.number || r.fell_off.number || r.drove_off.number || r.blocked || i % 15 == 0)
      std::printf("%3d x %6.2f z %6.2f y %6.2f head %5.2f m%d f%d d%d blk%d on%d air%d\n", i, v.x_m(), v.z_m(), v.elevation_m(), v.heading_rad(), r.mounted.number!=0, r.fell_off.number!=0, r.drove_off.number!=0, r.blocked, v.on_bridge(), v.airborne());
  }
}
}
