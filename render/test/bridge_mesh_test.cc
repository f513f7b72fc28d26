// The bridge drawn is the bridge driven: the mesh AppendBridge draws holds exactly the solids the
// physical vehicles meet, so no vehicle the physics moves sits inside a drawn deck or pier.
#include "render/bridge_mesh.h"

#include <cmath>
#include <numbers>
#include <vector>

#include <gtest/gtest.h>

#include "vehicle/bridge_solids.h"
#include "vehicle/physical_vehicle.h"
#include "vehicle/shipped_friction.h"

namespace dt {
namespace {

constexpr FeatureId kBridge{1, 1, 1};

// A 6 m bridge on flat ground at 10 m: ramp 1 from x 70 to 100, span to 140, ramp 2 to 170, at
// z = 200, 10 m wide (z 195..205).
Terrain BridgeTerrain(bool destroyed) {
  Terrain t(HeightGrid(201, 2.0, 10.0f, Material::kGrass));
  FeatureParams p = FeatureParams::Bridge(100, 200, 0.0, 10, 30, 40, 30, 6.0, 6.0);
  if (destroyed) p.status = BridgeStatus::kDestroyed;
  EXPECT_TRUE(t.Add(kBridge, p).ok());
  return t;
}

Mesh DrawnBridge(const Terrain& t) {
  Mesh mesh;
  AppendBridge(static_cast<const Bridge&>(*t.Find(kBridge)), t, mesh);
  return mesh;
}

// True if p lies inside the drawn (closed) solids: a ray straight up from it crosses their
// triangles an odd number of times. The ray is nudged off the grid the solids' edges lie on.
bool InsideDrawn(const Mesh& mesh, Eigen::Vector3d p) {
  p.x() += 1.234567e-6;
  p.z() += 2.345678e-6;
  int crossings = 0;
  for (size_t k = 0; k + 8 < mesh.triangle_xyz.size(); k += 9) {
    Eigen::Vector3d v[3];
    for (size_t i = 0; i < 3; ++i) {
      v[i] = Eigen::Vector3d(mesh.triangle_xyz[k + 3 * i], mesh.triangle_xyz[k + 3 * i + 1],
                             mesh.triangle_xyz[k + 3 * i + 2]);
    }
    // Barycentric coordinates of (p.x, p.z) in the triangle's plan.
    const double d = (v[1].x() - v[0].x()) * (v[2].z() - v[0].z()) -
                     (v[2].x() - v[0].x()) * (v[1].z() - v[0].z());
    if (std::abs(d) < 1e-12) continue;  // a vertical face: the ray runs beside it
    const double b1 =
        ((p.x() - v[0].x()) * (v[2].z() - v[0].z()) - (v[2].x() - v[0].x()) * (p.z() - v[0].z())) /
        d;
    const double b2 =
        ((v[1].x() - v[0].x()) * (p.z() - v[0].z()) - (p.x() - v[0].x()) * (v[1].z() - v[0].z())) /
        d;
    if (b1 < 0.0 || b2 < 0.0 || b1 + b2 > 1.0) continue;
    const double y = v[0].y() + b1 * (v[1].y() - v[0].y()) + b2 * (v[2].y() - v[0].y());
    crossings += y > p.y();
  }
  return crossings % 2 == 1;
}

// Points of the vehicle's hull box (belly to roof) on a 0.25 m grid, shrunk by the 0.1 m the
// physics lets a hull enter a solid (docs/vehicles.md "Hull collision").
std::vector<Eigen::Vector3d> HullPoints(const PhysicalVehicle& v) {
  const PhysicalVehicleType& t = v.type();
  const double inset = 0.1;
  const double L = t.base.length_m - 2 * inset, W = t.base.width_m - 2 * inset;
  const double lo = t.clearance_m - t.cg_height_m + inset;
  const double hi = t.hull_height_m - t.cg_height_m - inset;
  const Eigen::Matrix3d r = v.orientation().toRotationMatrix();
  std::vector<Eigen::Vector3d> out;
  const int na = static_cast<int>(std::ceil(L / 0.25)) + 1;
  const int nl = static_cast<int>(std::ceil(W / 0.25)) + 1;
  const int nh = static_cast<int>(std::ceil((hi - lo) / 0.25)) + 1;
  for (int i = 0; i < na; ++i) {
    for (int j = 0; j < nl; ++j) {
      for (int k = 0; k < nh; ++k) {
        const Eigen::Vector3d b(-L / 2 + L * i / (na - 1), lo + (hi - lo) * k / (nh - 1),
                                -W / 2 + W * j / (nl - 1));
        out.push_back(v.position_m() + r * b);
      }
    }
  }
  return out;
}

// Drives and returns the number of ticks in which a hull point sat inside the drawn bridge.
int TicksInsideDrawn(const Terrain& t, const Mesh& mesh, PhysicalVehicle& v, double speed_mps,
                     double seconds, double& min_x_m) {
  EXPECT_TRUE(v.Command(speed_mps, 0).ok());
  int inside = 0;
  min_x_m = INFINITY;
  for (int i = 0; i < static_cast<int>(seconds * 30); ++i) {
    EXPECT_TRUE(v.Advance(t, 1.0 / 30).ok());
    min_x_m = std::min(min_x_m, v.x_m());
    for (const Eigen::Vector3d& p : HullPoints(v)) {
      if (InsideDrawn(mesh, p)) {
        ++inside;
        break;
      }
    }
  }
  return inside;
}

TEST(BridgeMesh, EverySolidIsDrawnAndNothingElse) {
  for (const bool destroyed : {false, true}) {
    const Terrain t = BridgeTerrain(destroyed);
    const Mesh mesh = DrawnBridge(t);
    const std::vector<Solid> solids =
        BridgeSolids(static_cast<const Bridge&>(*t.Find(kBridge)), t.ground());
    EXPECT_EQ(mesh.triangle_vertex_count(), solids.size() * 6 * 2 * 3);
    for (const Solid& s : solids) {
      // Its middle is drawn solid; just above its top is not (nothing stands on a bridge solid).
      const double a = 0.5 * (s.a0_m + s.a1_m), r = 0.5 * (s.r0_m + s.r1_m);
      const Eigen::Vector3d at(s.origin_x_m + a * s.ux + r * s.uz, 0.0,
                               s.origin_z_m + a * s.uz - r * s.ux);
      const double top = s.TopAt(a), bottom = s.BottomAt(a);
      EXPECT_TRUE(InsideDrawn(mesh, {at.x(), 0.5 * (top + bottom), at.z()})) << destroyed;
      if (!s.deck) continue;  // a pier's top is under a deck
      EXPECT_FALSE(InsideDrawn(mesh, {at.x(), top + 0.05, at.z()})) << destroyed;
      EXPECT_FALSE(InsideDrawn(mesh, {at.x(), bottom - 0.05, at.z()})) << destroyed;
    }
  }
}

// Along under the span towards ramp 1: the tank passes between the piers at x 100 (columns at the
// deck's edges, not a wall across it) and stops where ramp 1's underside comes down to its roof,
// never inside the drawn deck.
TEST(BridgeMesh, ATankUnderTheSpanAndRampOneIsNeverInsideTheDrawnBridge) {
  const Terrain t = BridgeTerrain(false);
  const Mesh mesh = DrawnBridge(t);
  const PhysicalVehicleType tank = BuiltInPhysicalType("tank", ShippedFrictionTable()).value();
  auto v = PhysicalVehicle::Make(tank, t, 125, 200, std::numbers::pi).value();
  double min_x = 0.0;
  EXPECT_EQ(TicksInsideDrawn(t, mesh, v, 6.0, 12.0, min_x), 0);
  EXPECT_LT(min_x, 95.0);  // past the piers, under ramp 1
  EXPECT_NEAR(v.elevation_m(), 10.0, 0.1);
}

// A destroyed span's rubble stops vehicles, and it is drawn: a jeep driven at it from the side
// stops against drawn faces, never inside them.
TEST(BridgeMesh, DestroyedSpanRubbleIsDrawnWhereItStopsVehicles) {
  const Terrain t = BridgeTerrain(true);
  const Mesh mesh = DrawnBridge(t);
  EXPECT_TRUE(InsideDrawn(mesh, {120.0, 10.5, 200.0}));  // the rubble, 1 m high
  const PhysicalVehicleType jeep = BuiltInPhysicalType("jeep", ShippedFrictionTable()).value();
  auto v = PhysicalVehicle::Make(jeep, t, 120, 185, std::numbers::pi / 2).value();
  double min_x = 0.0;
  EXPECT_EQ(TicksInsideDrawn(t, mesh, v, 3.0, 8.0, min_x), 0);
  EXPECT_LT(v.z_m(), 195.0);  // stopped at the rubble
}

}  // namespace
}  // namespace dt
