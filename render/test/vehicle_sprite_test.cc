#include "render/vehicle_sprite.h"

#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

namespace dt {
namespace {

TEST(VehicleSprite, SpriteOfCopiesPoseAndSize) {
  Result<Vehicle> made = Vehicle::Make(TankType(), 50.0, 60.0, 0.4, 200.0, 200.0);
  ASSERT_TRUE(made.ok()) << made.error().message;
  Vehicle v = std::move(made).value();
  Orientation o;
  o.pitch_rad = 0.1;
  o.roll_rad = -0.2;
  o.elevation_m = 12.5;
  v.set_orientation(o);
  const VehicleSprite s = SpriteOf(v, {1, 2, 3, 255});
  EXPECT_EQ(s.x_m, 50.0);
  EXPECT_EQ(s.z_m, 60.0);
  EXPECT_EQ(s.y_m, 12.5);
  EXPECT_EQ(s.heading_rad, v.heading_rad());
  EXPECT_EQ(s.pitch_rad, 0.1);
  EXPECT_EQ(s.roll_rad, -0.2);
  EXPECT_EQ(s.length_m, TankType().length_m);
  EXPECT_EQ(s.width_m, TankType().width_m);
  EXPECT_DOUBLE_EQ(s.height_m, kSpriteHeightPerWidth * TankType().width_m);
  EXPECT_EQ(s.colour, (Rgba{1, 2, 3, 255}));
  v.Kill();
  EXPECT_EQ(SpriteOf(v, {1, 2, 3, 255}).colour, kDeadVehicleColour);
}

// The box's corners, recovered from the mesh's vertices.
double MaxY(const Mesh& m) {
  double y = -1e9;
  for (size_t k = 1; k < m.triangle_xyz.size(); k += 3) y = std::max(y, double{m.triangle_xyz[k]});
  return y;
}

TEST(VehicleSprite, PitchRaisesTheNoseAndRollLowersTheRight) {
  VehicleSprite level;
  level.heading_rad = 0.0;  // facing +x; the right side is -z
  Mesh flat;
  AppendVehicle(level, flat);
  EXPECT_NEAR(MaxY(flat), level.height_m, 1e-5);
  // Pitch up: the highest point is the nose's roof edge, ahead (+x).
  VehicleSprite pitched = level;
  pitched.pitch_rad = 0.3;
  Mesh pm;
  AppendVehicle(pitched, pm);
  double best_y = -1e9, best_x = 0.0;
  for (size_t k = 0; k < pm.triangle_xyz.size(); k += 3) {
    if (pm.triangle_xyz[k + 1] > best_y) {
      best_y = pm.triangle_xyz[k + 1];
      best_x = pm.triangle_xyz[k];
    }
  }
  EXPECT_GT(best_y, level.height_m);
  EXPECT_GT(best_x, 0.0);
  // Roll right: the lowest roof corner is on the right (-z), the highest on the left (+z).
  VehicleSprite rolled = level;
  rolled.roll_rad = 0.3;
  Mesh rm;
  AppendVehicle(rolled, rm);
  double top_y = -1e9, top_z = 0.0;
  for (size_t k = 0; k < rm.triangle_xyz.size(); k += 3) {
    if (rm.triangle_xyz[k + 1] > top_y) {
      top_y = rm.triangle_xyz[k + 1];
      top_z = rm.triangle_xyz[k + 2];
    }
  }
  EXPECT_GT(top_z, 0.0);
}

}  // namespace
}  // namespace dt
