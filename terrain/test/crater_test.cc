#include "terrain/crater.h"

#include <cmath>
#include <numbers>
#include <random>

#include <gtest/gtest.h>

namespace dt {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr FeatureId kId{1, 2, 3};

// 100 m x 100 m, 1 m spacing. Craters keep offsets above the ground, so its shape is irrelevant
// here; terrain_test.cc checks the draping.
HeightGrid Ground() { return HeightGrid(101, 1.0, 3.0f, Material::kDirt); }

std::unique_ptr<Feature> Make(const FeatureParams& params, const HeightGrid& ground = Ground()) {
  auto made = MakeCrater(kId, params, ground);
  if (!made) ADD_FAILURE() << made.error().message;
  return made ? std::move(made).value() : nullptr;
}

const Crater& AsCrater(const std::unique_ptr<Feature>& f) { return static_cast<const Crater&>(*f); }

double OffsetAt(const Feature& f, double x, double z) {
  auto o = f.OffsetAboveGround(x, z);
  EXPECT_TRUE(o.has_value()) << "(" << x << ", " << z << ") not covered";
  return o.value_or(NAN);
}

TEST(Crater, RimIsRaisedAtTheRimRingsAndLevelAtCentreFloorAndEdge) {
  const double r = 10.0;
  auto f = Make(FeatureParams::Crater(50, 50, r));
  const Crater& c = AsCrater(f);
  const double rim = kCraterRimHeightFraction * r;
  ASSERT_GT(rim, 0.0);
  EXPECT_DOUBLE_EQ(c.rim_height_m(), rim);
  EXPECT_DOUBLE_EQ(OffsetAt(c, 50, 50), 0.0);
  for (int k = 0; k < kCraterSpokes; ++k) {
    const double a = k * kPi / 8;
    for (int ring = 0; ring < kCraterRings; ++ring) {
      const CraterVertex v = c.Vertex(k, ring);
      const double ring_r = kCraterRingFractions[ring] * r;
      EXPECT_NEAR(v.x_m, 50 + ring_r * std::cos(a), 1e-12);
      EXPECT_NEAR(v.z_m, 50 + ring_r * std::sin(a), 1e-12);
      const double expected = (ring == 1 || ring == 2) ? rim : 0.0;
      EXPECT_DOUBLE_EQ(v.offset_m, expected) << k << "," << ring;
      EXPECT_NEAR(OffsetAt(c, v.x_m, v.z_m), expected, 1e-12) << k << "," << ring;
    }
    // Halfway between the rim rings, between spokes: still the full rim.
    const double mid = a + kPi / 16;
    EXPECT_NEAR(OffsetAt(c, 50 + 0.7 * r * std::cos(mid), 50 + 0.7 * r * std::sin(mid)), rim,
                1e-12);
    // The floor inside ring 0 is the ground.
    EXPECT_DOUBLE_EQ(OffsetAt(c, 50 + 0.2 * r * std::cos(mid), 50 + 0.2 * r * std::sin(mid)), 0.0);
    // Halfway up the inner slope.
    EXPECT_NEAR(OffsetAt(c, 50 + 0.5 * r * std::cos(mid), 50 + 0.5 * r * std::sin(mid)), rim / 2,
                1e-12);
    // Beyond the radius nothing is covered.
    EXPECT_FALSE(
        c.OffsetAboveGround(50 + 1.001 * r * std::cos(mid), 50 + 1.001 * r * std::sin(mid)));
    EXPECT_FALSE(c.Covers(50 + 1.001 * r * std::cos(mid), 50 + 1.001 * r * std::sin(mid)));
    EXPECT_TRUE(c.Covers(50 + 0.999 * r * std::cos(mid), 50 + 0.999 * r * std::sin(mid)));
  }
}

// A crater whose 64 vertices all have different offsets, so interpolation errors show.
FeatureParams IrregularCrater(uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> offset(-1.0, 4.0);
  FeatureParams p = FeatureParams::Crater(50, 50, 12.0);
  for (int k = 0; k < kCraterSpokes; ++k) {
    for (int ring = 0; ring < kCraterRings; ++ring) {
      p.vertex_edits.push_back({static_cast<uint8_t>(k), static_cast<uint8_t>(ring), offset(rng)});
    }
  }
  return p;
}

TEST(Crater, ElevationIsContinuousAcrossSpokesAndRings) {
  for (uint64_t seed : {1u, 2u, 3u}) {
    auto f = Make(IrregularCrater(seed));
    const Crater& c = AsCrater(f);
    const double eps = 1e-7;
    // Offsets span 5 m over mesh cells at least ~1.8 m wide, so a continuous surface changes by
    // about 6e-7 m over a 2e-7 m step; a seam would show as a jump of the order of metres.
    const double tolerance = 5e-6;
    for (int k = 0; k < kCraterSpokes; ++k) {
      const double a = k * kPi / 8;
      for (double q = 0.05; q < 1.0; q += 0.05) {
        const double rr = q * 12.0;
        // Across spoke k: a step of eps either side, perpendicular to the spoke.
        const double px = 50 + rr * std::cos(a), pz = 50 + rr * std::sin(a);
        const double nx = -std::sin(a) * eps, nz = std::cos(a) * eps;
        EXPECT_NEAR(OffsetAt(c, px + nx, pz + nz), OffsetAt(c, px - nx, pz - nz), tolerance)
            << "spoke " << k << " q " << q;
      }
      for (int ring = 0; ring < kCraterRings - 1; ++ring) {
        for (double da : {0.0, 0.3, 0.77}) {
          const double b = a + da * kPi / 8;
          const double rr = kCraterRingFractions[ring] * 12.0;
          EXPECT_NEAR(OffsetAt(c, 50 + (rr + eps) * std::cos(b), 50 + (rr + eps) * std::sin(b)),
                      OffsetAt(c, 50 + (rr - eps) * std::cos(b), 50 + (rr - eps) * std::sin(b)),
                      tolerance)
              << "ring " << ring << " spoke " << k;
        }
      }
    }
    // Toward the centre every spoke meets the ground.
    EXPECT_NEAR(OffsetAt(c, 50 + 1e-6, 50 - 1e-6), 0.0, 1e-5);
  }
}

TEST(Crater, VertexEditChangesOnlyItsNeighbourhood) {
  const double r = 20.0;
  const FeatureParams plain = FeatureParams::Crater(50, 50, r);
  const int spoke = 3, ring = 1;
  const FeatureParams edited = WithCraterVertexEdit(plain, {uint8_t(spoke), uint8_t(ring), 7.5});
  auto a = Make(plain);
  auto b = Make(edited);
  EXPECT_DOUBLE_EQ(AsCrater(b).Vertex(spoke, ring).offset_m, 7.5);
  const CraterVertex v = AsCrater(b).Vertex(spoke, ring);
  EXPECT_NEAR(OffsetAt(*b, v.x_m, v.z_m), 7.5, 1e-12);
  int changed = 0;
  for (double x = 29.05; x < 71; x += 0.2) {
    for (double z = 29.05; z < 71; z += 0.2) {
      const auto oa = a->OffsetAboveGround(x, z);
      const auto ob = b->OffsetAboveGround(x, z);
      ASSERT_EQ(oa.has_value(), ob.has_value());
      if (!oa || std::abs(*oa - *ob) < 1e-12) continue;
      ++changed;
      // Only the four mesh cells around the vertex: sectors 2 and 3, rings 0 to 2.
      const double dist = std::hypot(x - 50, z - 50);
      double angle = std::atan2(z - 50, x - 50);
      if (angle < 0) angle += 2 * kPi;
      EXPECT_GT(angle, 2 * kPi / 8 - 1e-9) << x << "," << z;
      EXPECT_LT(angle, 4 * kPi / 8 + 1e-9) << x << "," << z;
      EXPECT_GT(dist, kCraterRingFractions[0] * r - 1e-9) << x << "," << z;
      EXPECT_LT(dist, kCraterRingFractions[2] * r + 1e-9) << x << "," << z;
    }
  }
  EXPECT_GT(changed, 100);
  // Every vertex other than the edited one is unchanged.
  for (int k = 0; k < kCraterSpokes; ++k) {
    for (int g = 0; g < kCraterRings; ++g) {
      if (k == spoke && g == ring) continue;
      EXPECT_EQ(AsCrater(a).Vertex(k, g).offset_m, AsCrater(b).Vertex(k, g).offset_m);
    }
  }
}

TEST(Crater, EditsToStandardValuesGiveTheStandardSurface) {
  // The general (edited) interpolation and the standard profile must agree.
  const double r = 15.0;
  FeatureParams p = FeatureParams::Crater(50, 50, r);
  p = WithCraterVertexEdit(p, {5, 2, StandardCraterRingOffset(r, 2)});
  auto plain = Make(FeatureParams::Crater(50, 50, r));
  auto edited = Make(p);
  ASSERT_TRUE(AsCrater(edited).has_vertex_edits());
  ASSERT_FALSE(AsCrater(plain).has_vertex_edits());
  for (double x = 34.9; x < 65.2; x += 0.37) {
    for (double z = 34.9; z < 65.2; z += 0.37) {
      const auto a = plain->OffsetAboveGround(x, z);
      const auto b = edited->OffsetAboveGround(x, z);
      ASSERT_EQ(a.has_value(), b.has_value());
      if (a) {
        EXPECT_NEAR(*a, *b, 1e-12) << x << "," << z;
      }
    }
  }
}

TEST(Crater, SectorsFoundByComparisonMatchTheAngle) {
  // Rim vertices of spoke k at offset k + 1: between rings 1 and 2 the offset interpolates
  // between adjacent spokes, so it reveals the sector and the fraction within it.
  const double r = 10.0;
  FeatureParams p = FeatureParams::Crater(50, 50, r);
  for (int k = 0; k < kCraterSpokes; ++k) {
    for (int ring : {1, 2}) p = WithCraterVertexEdit(p, {uint8_t(k), uint8_t(ring), k + 1.0});
  }
  auto f = Make(p);
  for (int step = 0; step < 16 * 64; ++step) {
    const double angle = step * (2 * kPi / (16 * 64));
    const double x = 50 + 7 * std::cos(angle), z = 50 + 7 * std::sin(angle);
    const int k = step / 64;
    const double frac = (step % 64) / 64.0;
    const double next = k == 15 ? 1.0 : k + 2.0;
    const double expected = (k + 1.0) + frac * (next - (k + 1.0));
    EXPECT_NEAR(OffsetAt(*f, x, z), expected, 0.0026 * std::abs(next - (k + 1.0)) + 1e-9)
        << "step " << step;
  }
}

TEST(Crater, MayCoverTestsTheCircleNotItsBox) {
  auto f = Make(FeatureParams::Crater(50, 50, 10));
  // The corner of the bounding box is outside the circle.
  EXPECT_TRUE(f->Bounds().Intersects({58, 58, 60, 60}));
  EXPECT_FALSE(f->MayCover({58, 58, 60, 60}));
  EXPECT_TRUE(f->MayCover({56, 56, 58, 58}));   // 8.49 m from the centre at its nearest
  EXPECT_TRUE(f->MayCover({0, 49, 40.5, 51}));  // reaches in from the side
  EXPECT_FALSE(f->MayCover({0, 49, 39.9, 51}));
  EXPECT_TRUE(f->MayCover({45, 45, 46, 46}));  // inside
  EXPECT_TRUE(f->MayCover({0, 0, 100, 100}));  // contains it
  // MayCover is never false where a point is covered.
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> pos(35, 65), size(0.01, 3);
  for (int n = 0; n < 2000; ++n) {
    const double x = pos(rng), z = pos(rng), w = size(rng), h = size(rng);
    const Rect rect{x, z, x + w, z + h};
    bool covered = false;
    for (double sx : {0.0, 0.5, 1.0}) {
      for (double sz : {0.0, 0.5, 1.0}) covered |= f->Covers(x + sx * w, z + sz * h);
    }
    if (covered) {
      EXPECT_TRUE(f->MayCover(rect)) << x << "," << z;
    }
  }
}

TEST(Crater, ParamsRebuildTheSameCraterAndMaterialResolvesFromTheGround) {
  HeightGrid ground = Ground();
  ground.set_soil(ground.SquareAt(40.2, 60.3), ground.HalfAt(40.2, 60.3), Material::kSand);
  FeatureParams p = WithCraterVertexEdit(FeatureParams::Crater(40.2, 60.3, 5.5), {9, 3, 0.25});
  auto f = Make(p, ground);
  EXPECT_EQ(f->params(), p);
  EXPECT_EQ(f->params().material, Material::kFromGround);
  EXPECT_EQ(f->material(), Material::kSand);
  EXPECT_EQ(f->id(), kId);
  auto again = Make(f->params(), ground);
  EXPECT_EQ(again->params(), p);
  for (double x = 34; x < 46; x += 0.31) {
    for (double z = 54; z < 66; z += 0.31) {
      EXPECT_EQ(f->OffsetAboveGround(x, z), again->OffsetAboveGround(x, z));
    }
  }
  // A given material is kept.
  auto rock = Make(FeatureParams::Crater(40.2, 60.3, 5.5, Material::kRock), ground);
  EXPECT_EQ(rock->material(), Material::kRock);
  EXPECT_EQ(rock->params().material, Material::kRock);
}

TEST(Crater, BadParametersAreRefusedWithTheValue) {
  const HeightGrid ground = Ground();
  auto refused = [&](const FeatureParams& p, const std::string& needle) {
    auto made = MakeCrater(kId, p, ground);
    ASSERT_FALSE(made.ok());
    EXPECT_NE(made.error().message.find(needle), std::string::npos) << made.error().message;
  };
  FeatureParams p = FeatureParams::Crater(50, 50, 5);
  p.direction_rad = 0.5;
  refused(p, "direction_rad");
  p = FeatureParams::Crater(50, 50, 5);
  p.width_m = 2;
  refused(p, "width_m");
  refused(FeatureParams::Crater(50, 50, 0), "radius");
  refused(FeatureParams::Crater(50, 50, -3), "-3");
  refused(FeatureParams::Crater(150, 50, 5), "off the terrain");
  refused(FeatureParams::Crater(NAN, 50, 5), "x_m");
  refused(FeatureParams::Berm(50, 50, 0, 10, 3, 1), "a crater maker given a berm");
}

TEST(Crater, WithVertexEditKeepsEditsSortedAndReplaces) {
  FeatureParams p = FeatureParams::Crater(50, 50, 5);
  p = WithCraterVertexEdit(p, {4, 2, 1.0});
  p = WithCraterVertexEdit(p, {1, 3, 2.0});
  p = WithCraterVertexEdit(p, {4, 0, 3.0});
  p = WithCraterVertexEdit(p, {4, 2, 4.0});
  const std::vector<CraterVertexEdit> expected = {{1, 3, 2.0}, {4, 0, 3.0}, {4, 2, 4.0}};
  EXPECT_EQ(p.vertex_edits, expected);
  EXPECT_TRUE(ValidateFeatureParams(p).ok());
  EXPECT_THROW(WithCraterVertexEdit(p, {16, 0, 1.0}), std::invalid_argument);
  EXPECT_THROW(WithCraterVertexEdit(p, {0, 4, 1.0}), std::invalid_argument);
  EXPECT_THROW(WithCraterVertexEdit(FeatureParams::Berm(1, 1, 0, 1, 1, 1), {0, 0, 1.0}),
               std::invalid_argument);
  auto f = Make(FeatureParams::Crater(50, 50, 5));
  EXPECT_THROW(AsCrater(f).Vertex(16, 0), std::out_of_range);
  EXPECT_THROW(AsCrater(f).Vertex(0, -1), std::out_of_range);
}

}  // namespace
}  // namespace dt
