// Craters below the ground, ditches, berm lines and areas, and how they compose with the others.
#include <cmath>
#include <numbers>
#include <string>

#include <gtest/gtest.h>

#include "terrain/area_feature.h"
#include "terrain/crater.h"
#include "terrain/polyline_earthwork.h"
#include "terrain/terrain.h"

namespace dt {
namespace {

constexpr float kGround = 3.0f;
Terrain Flat() { return Terrain(HeightGrid(101, 1.0, kGround, Material::kGrass)); }
const FeatureId kA{1, 1, 1}, kB{1, 1, 2}, kC{1, 1, 3};

void ExpectRefused(const FeatureParams& p, const std::string& needle) {
  const Status s = ValidateFeatureParams(p);
  ASSERT_FALSE(s.ok()) << needle;
  EXPECT_NE(s.error().message.find(needle), std::string::npos) << s.error().message;
}

TEST(DeepCrater, FloorLiesItsDepthBelowTheGroundAndTheRimAboveIt) {
  Terrain t = Flat();
  ASSERT_TRUE(t.Add(kA, FeatureParams::DeepCrater(50, 50, 10, 3, Material::kSand)).ok());
  EXPECT_DOUBLE_EQ(t.ElevationAt(50, 50), kGround - 3.0);
  EXPECT_DOUBLE_EQ(t.ElevationAt(54, 50), kGround - 3.0);           // ring 0: edge of the floor
  EXPECT_NEAR(t.ElevationAt(55, 50), kGround - 3.0 + 2.25, 1e-12);  // halfway up the wall
  EXPECT_DOUBLE_EQ(t.ElevationAt(57, 50), kGround + 1.5);           // the rim
  EXPECT_DOUBLE_EQ(t.ElevationAt(60, 50), kGround);                 // ring 3
  EXPECT_EQ(t.SoilAt(50, 50), Material::kSand);
  EXPECT_EQ(t.Find(kA)->params(), FeatureParams::DeepCrater(50, 50, 10, 3, Material::kSand));
}

TEST(DeepCrater, NegativeVertexEditsCutBelowTheGround) {
  Terrain t = Flat();
  FeatureParams p = WithCraterVertexEdit(FeatureParams::Crater(50, 50, 10), {0, 0, -2.0});
  ASSERT_TRUE(t.Add(kA, p).ok());
  EXPECT_DOUBLE_EQ(t.ElevationAt(54, 50), kGround - 2.0);  // the vertex (spoke 0, ring 0)
  EXPECT_DOUBLE_EQ(t.ElevationAt(50, 54), kGround);        // spoke 4 keeps the standard floor
}

TEST(DeepCrater, DepthOutOfRangeIsRefusedNamingTheField) {
  ExpectRefused(FeatureParams::DeepCrater(50, 50, 10, -1), "crater depth_m height_m[0]");
  ExpectRefused(FeatureParams::DeepCrater(50, 50, 10, 101), "crater depth_m height_m[0]");
}

// A ditch along +x from (20, 50) to (80, 50): 2 m deep, 6 m wide at the top, sides 1.5 m wide.
FeatureParams StraightDitch(double spoil_h = 0.0, double spoil_w = 0.0) {
  return FeatureParams::Ditch({{20, 50, 2, 6}, {80, 50, 2, 6}}, 1.5, spoil_h, spoil_w,
                              Material::kDirt);
}

TEST(Ditch, CrossSectionIsAFlatFloorWithSlopingSides) {
  Terrain t = Flat();
  ASSERT_TRUE(t.Add(kA, StraightDitch()).ok());
  EXPECT_DOUBLE_EQ(t.ElevationAt(50, 50), kGround - 2.0);
  EXPECT_DOUBLE_EQ(t.ElevationAt(50, 51.5), kGround - 2.0);   // floor edge: 3 - 1.5 from centre
  EXPECT_DOUBLE_EQ(t.ElevationAt(50, 52.25), kGround - 1.0);  // halfway up the side
  EXPECT_DOUBLE_EQ(t.ElevationAt(50, 53), kGround);           // top edge
  EXPECT_FALSE(t.Find(kA)->Covers(50, 53.5));
  EXPECT_EQ(t.SoilAt(50, 50), Material::kDirt);
  // The end piece tapers over the side run.
  EXPECT_DOUBLE_EQ(t.ElevationAt(19.25, 50), kGround - 1.0);
  EXPECT_FALSE(t.Find(kA)->Covers(18.4, 50));
}

TEST(Ditch, SpoilBermLiesOnTheRightOfTheDirectionOfTravel) {
  Terrain t = Flat();
  ASSERT_TRUE(t.Add(kA, StraightDitch(1.2, 3)).ok());
  EXPECT_DOUBLE_EQ(t.ElevationAt(50, 50 - 4.5), kGround + 1.2);  // spoil crest, right = -z
  EXPECT_DOUBLE_EQ(t.ElevationAt(50, 50 + 4.5), kGround);        // nothing on the left
  EXPECT_FALSE(t.Find(kA)->Covers(50, 54.5));
}

TEST(Ditch, BadCrossSectionsAreRefusedNamingTheField) {
  ExpectRefused(FeatureParams::Ditch({{20, 50, 2, 2}, {80, 50, 2, 6}}, 1.5),
                "ditch points[0].width_m = 2 is less than twice the side run");
  ExpectRefused(FeatureParams::Ditch({{20, 50, 0, 6}, {80, 50, 2, 6}}, 1.5),
                "ditch points[0].height_m");
  ExpectRefused(FeatureParams::Ditch({{20, 50, 2, 6}}, 1.5), "ditch points: 1 given");
  ExpectRefused(FeatureParams::Ditch({{20, 50, 2, 6}, {80, 50, 2, 6}, {20, 51, 2, 6}}, 1.5),
                "ditch points[1]: the line turns by");
  ExpectRefused(FeatureParams::Ditch({{20, 50, 2, 6}, {80, 50, 2, 6}}, 1.5, 1.0, 0.0),
                "ditch spoil width_m length_m[1]");
  FeatureParams moved = StraightDitch();
  moved.x_m = 21;
  ExpectRefused(moved, "ditch x_m, z_m (21, 50) must be points[0]");
  FeatureParams crater = FeatureParams::Crater(50, 50, 5);
  crater.points = {{50, 50, 0, 0}};
  ExpectRefused(crater, "crater cannot carry points");
}

TEST(BermLine, CornerIsBevelledNotRounded) {
  // (10, 50) -> (50, 50) -> (50, 90): a left turn of 90 degrees at (50, 50); the outside of the
  // corner is the south-east. Base width 12, crest 4 m wide, 2 m high.
  Terrain t = Flat();
  ASSERT_TRUE(
      t.Add(kA, FeatureParams::BermLine({{10, 50, 2, 12}, {50, 50, 2, 12}, {50, 90, 2, 12}})).ok());
  const Feature* f = t.Find(kA);
  // On the bisector, a point d out along each axis is 2 d from the chord's parallel through the
  // corner (distance times 1 / cos 45 deg), so the chord is at d = 3: a point 3.1 m out on each
  // axis is 4.4 m from the corner, inside a rounded joint's 6 m, but beyond the chord.
  EXPECT_FALSE(f->Covers(53.1, 46.9));
  EXPECT_DOUBLE_EQ(t.ElevationAt(51, 49), kGround + 2.0);    // on the crest across the corner
  EXPECT_NEAR(t.ElevationAt(52, 48), kGround + 1.0, 1e-12);  // halfway down the bevel
  // The inside of the corner is whole.
  EXPECT_DOUBLE_EQ(t.ElevationAt(48, 52), kGround + 2.0);
  // Continuous through the joint along the crest's outer edge.
  for (double a = -2.0; a <= 2.0; a += 0.01) {
    const double x = 50 + 1.9 * std::cos(a), z = 50 + 1.9 * std::sin(a);
    EXPECT_NEAR(t.ElevationAt(x, z), t.ElevationAt(x + 1e-7, z + 1e-7), 1e-5) << a;
  }
}

TEST(BermLine, SectionVariesAlongEachSegment) {
  Terrain t = Flat();
  ASSERT_TRUE(t.Add(kA, FeatureParams::BermLine({{20, 50, 1, 6}, {80, 50, 3, 12}})).ok());
  EXPECT_DOUBLE_EQ(t.ElevationAt(50, 50), kGround + 2.0);
  EXPECT_FALSE(t.Find(kA)->Covers(50, 54.6));  // half width 4.5 at the middle
  EXPECT_TRUE(t.Find(kA)->Covers(50, 54.4));
}

TEST(Polyline, BreachLeavesAGapOfBareGroundAndValidPieces) {
  const FeatureParams ditch = StraightDitch();
  auto pieces = BreachPolyline(ditch, 30, 4);
  ASSERT_TRUE(pieces.ok()) << pieces.error().message;
  ASSERT_EQ(pieces.value().size(), 2u);
  Terrain t = Flat();
  ASSERT_TRUE(t.Add(kA, pieces.value()[0]).ok());
  ASSERT_TRUE(t.Add(kB, pieces.value()[1]).ok());
  for (double x = 48.0; x <= 52.0; x += 0.25) EXPECT_DOUBLE_EQ(t.ElevationAt(x, 50), kGround) << x;
  EXPECT_DOUBLE_EQ(t.ElevationAt(40, 50), kGround - 2.0);
  EXPECT_DOUBLE_EQ(t.ElevationAt(60, 50), kGround - 2.0);
  EXPECT_DOUBLE_EQ(pieces.value()[0].points.back().x_m, 48 - 1.5);
  EXPECT_FALSE(BreachPolyline(ditch, 61, 4).ok());
  EXPECT_FALSE(BreachPolyline(ditch, 30, 0).ok());
  // A gap at the very start leaves one piece; a gap over everything leaves none.
  EXPECT_EQ(BreachPolyline(ditch, 0, 4).value().size(), 1u);
  EXPECT_EQ(BreachPolyline(ditch, 30, 70).value().size(), 0u);
}

TEST(Composition, BermAcrossADitchRidesDownIntoIt) {
  Terrain t = Flat();
  ASSERT_TRUE(t.Add(kA, StraightDitch()).ok());
  ASSERT_TRUE(t.Add(kB, FeatureParams::Berm(50, 40, std::numbers::pi / 2, 20, 9, 1.5)).ok());
  EXPECT_DOUBLE_EQ(t.ElevationAt(50, 50), kGround + 1.5 - 2.0);
  EXPECT_EQ(t.SoilAt(50, 50), t.Find(kB)->material());  // the raise is on top
  // Two holes: the deeper wins.
  ASSERT_TRUE(t.Add(kC, FeatureParams::DeepCrater(30, 50, 5, 4)).ok());
  EXPECT_DOUBLE_EQ(t.ElevationAt(30, 50), kGround - 4.0);
}

FeatureParams Square(double x0, double z0, double side, Material m, double level = 0.0) {
  return FeatureParams::Area(
      {{x0, z0, 0, 0}, {x0 + side, z0, 0, 0}, {x0 + side, z0 + side, 0, 0}, {x0, z0 + side, 0, 0}},
      m, level);
}

TEST(Area, ChangesTheSoilInsideButNotTheHeight) {
  Terrain t = Flat();
  ASSERT_TRUE(t.Add(kA, Square(10, 10, 20, Material::kMud)).ok());
  EXPECT_EQ(t.SoilAt(20, 20), Material::kMud);
  EXPECT_EQ(t.SoilAt(35, 20), Material::kGrass);
  EXPECT_DOUBLE_EQ(t.ElevationAt(20, 20), kGround);
  // Oil over mud wins wherever they overlap, whichever came first.
  ASSERT_TRUE(t.Add(kB, Square(25, 10, 20, Material::kOil)).ok());
  EXPECT_EQ(t.SoilAt(27, 20), Material::kOil);
  EXPECT_EQ(t.SoilAt(20, 20), Material::kMud);
  // A burnt area over a berm: the soil is burnt, the height the berm's.
  ASSERT_TRUE(t.Add(kC, FeatureParams::Berm(60, 20, 0, 20, 6, 2, Material::kDirt)).ok());
  ASSERT_TRUE(t.Add({1, 1, 4}, Square(55, 10, 20, Material::kBurnt)).ok());
  EXPECT_EQ(t.SoilAt(65, 20), Material::kBurnt);
  EXPECT_DOUBLE_EQ(t.ElevationAt(65, 20), kGround + 2.0);
}

TEST(Area, WaterFillsLowGroundToItsLevel) {
  Terrain t = Flat();
  // A deep crater, then a flood over it whose level is 1 m below the ground: only the hole fills.
  ASSERT_TRUE(t.Add(kA, FeatureParams::DeepCrater(50, 50, 10, 3)).ok());
  ASSERT_TRUE(t.Add(kB, Square(30, 30, 40, Material::kWater, kGround - 1.0)).ok());
  EXPECT_EQ(t.WaterLevelAt(50, 50), kGround - 1.0);
  EXPECT_EQ(t.SoilAt(50, 50), Material::kWater);
  EXPECT_DOUBLE_EQ(t.ElevationAt(50, 50), kGround - 3.0);  // vehicles drive on the bed
  EXPECT_FALSE(t.WaterLevelAt(35, 35).has_value());        // dry ground inside the polygon
  EXPECT_EQ(t.SoilAt(35, 35), Material::kGrass);
  EXPECT_FALSE(t.WaterLevelAt(57, 50).has_value());  // the rim stands above the water
  EXPECT_FALSE(t.WaterLevelAt(80, 80).has_value());  // outside the polygon
}

TEST(Area, BadAreasAreRefusedNamingTheField) {
  ExpectRefused(Square(10, 10, 20, Material::kFromGround), "area material must be a soil");
  ExpectRefused(Square(10, 10, 20, Material::kWater, 2e4), "area water level height_m[0]");
  FeatureParams p = Square(10, 10, 20, Material::kMud);
  p.height_m[0] = 1;
  ExpectRefused(p, "height_m[0] (a water level; the material is not water)");
  p = Square(10, 10, 20, Material::kMud);
  p.points[2].width_m = 1;
  ExpectRefused(p, "area points[2] height_m 0 and width_m 1 must be 0");
  p = Square(10, 10, 20, Material::kMud);
  p.points.resize(2);
  ExpectRefused(p, "area points: 2 given, needs 3 to 32");
}

TEST(Area, AFeatureOffTheTerrainIsRefused) {
  Terrain t = Flat();
  EXPECT_FALSE(t.Add(kA, Square(90, 90, 20, Material::kMud)).ok());
  EXPECT_FALSE(t.Add(kB, FeatureParams::Ditch({{50, 50, 2, 6}, {99, 50, 2, 6}}, 1.5)).ok());
  EXPECT_EQ(t.feature_count(), 0u);
}

}  // namespace
}  // namespace dt
