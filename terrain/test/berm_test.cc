#include "terrain/berm.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

#include <gtest/gtest.h>

#include "terrain/berm_operations.h"

namespace dt {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr FeatureId kId{1, 1, 9};

HeightGrid Ground() { return HeightGrid(101, 1.0, 0.0f, Material::kGrass); }

std::unique_ptr<Feature> Make(const FeatureParams& params, const HeightGrid& ground = Ground()) {
  auto made = MakeBerm(kId, params, ground);
  if (!made) ADD_FAILURE() << made.error().message;
  return made ? std::move(made).value() : nullptr;
}

const Berm& AsBerm(const std::unique_ptr<Feature>& f) { return static_cast<const Berm&>(*f); }

// The ground point `along` metres along the crest and `left` metres to its left.
struct Frame {
  double x, z, dir;
  double X(double along, double left) const {
    return x + along * std::cos(dir) - left * std::sin(dir);
  }
  double Z(double along, double left) const {
    return z + along * std::sin(dir) + left * std::cos(dir);
  }
};

double OffsetAt(const Feature& f, double x, double z) {
  auto o = f.OffsetAboveGround(x, z);
  EXPECT_TRUE(o.has_value()) << "(" << x << ", " << z << ") not covered";
  return o.value_or(NAN);
}

TEST(Berm, CrossSectionIsATrapezoid) {
  // Width 6: top 2 m wide at full height, each side slope runs 2 m.
  for (double dir : {0.0, 0.7, kPi / 2, -2.5}) {
    const Frame fr{50, 50, dir};
    auto f = Make(FeatureParams::Berm(50, 50, dir, 30, 6, 2));
    const Berm& b = AsBerm(f);
    EXPECT_DOUBLE_EQ(b.slope_run_m(), 2.0);
    for (double along : {0.0, 0.5, 12.3, 30.0}) {
      EXPECT_NEAR(OffsetAt(b, fr.X(along, 0), fr.Z(along, 0)), 2.0, 1e-12) << dir;
      EXPECT_NEAR(OffsetAt(b, fr.X(along, 0.999), fr.Z(along, 0.999)), 2.0, 1e-12);
      EXPECT_NEAR(OffsetAt(b, fr.X(along, -0.999), fr.Z(along, -0.999)), 2.0, 1e-12);
      EXPECT_NEAR(OffsetAt(b, fr.X(along, 2), fr.Z(along, 2)), 1.0, 1e-12);
      EXPECT_NEAR(OffsetAt(b, fr.X(along, -2.5), fr.Z(along, -2.5)), 0.5, 1e-12);
      EXPECT_NEAR(OffsetAt(b, fr.X(along, 2.9999), fr.Z(along, 2.9999)), 1e-4, 1e-9);
      EXPECT_FALSE(b.Covers(fr.X(along, 3.001), fr.Z(along, 3.001)));
      EXPECT_FALSE(b.OffsetAboveGround(fr.X(along, -3.001), fr.Z(along, -3.001)));
    }
  }
}

TEST(Berm, EndPiecesSlopeDownOverTheSideSlopeRun) {
  const Frame fr{20, 30, 0.3};
  auto f = Make(FeatureParams::Berm(20, 30, 0.3, 25, 6, 3));
  // The crest runs over [0, 25]; the end pieces over [-2, 0] and [25, 27].
  EXPECT_NEAR(OffsetAt(*f, fr.X(-1, 0), fr.Z(-1, 0)), 1.5, 1e-12);
  EXPECT_NEAR(OffsetAt(*f, fr.X(26, 0), fr.Z(26, 0)), 1.5, 1e-12);
  EXPECT_NEAR(OffsetAt(*f, fr.X(26.5, 0), fr.Z(26.5, 0)), 0.75, 1e-12);
  // On the side slope of an end piece: both slopes apply (bilinear over the mesh cell).
  EXPECT_NEAR(OffsetAt(*f, fr.X(-1, 2), fr.Z(-1, 2)), 3 * 0.5 * 0.5, 1e-12);
  EXPECT_NEAR(OffsetAt(*f, fr.X(-1.9999, 0), fr.Z(-1.9999, 0)), 0.0, 1e-3);
  EXPECT_FALSE(f->Covers(fr.X(-2.01, 0), fr.Z(-2.01, 0)));
  EXPECT_FALSE(f->Covers(fr.X(27.01, 0), fr.Z(27.01, 0)));
}

TEST(Berm, MeshHasElevenLengthLinesAndFourWidthLines) {
  const Frame fr{40, 40, 1.1};
  auto f = Make(FeatureParams::Berm(40, 40, 1.1, 20, 9, 1.5));
  const Berm& b = AsBerm(f);
  const double lefts[] = {-4.5, -1.5, 1.5, 4.5};
  for (int i = 0; i < kBermLengthLines; ++i) {
    for (int w = 0; w < kBermWidthLines; ++w) {
      const BermVertex v = b.Vertex(i, w);
      EXPECT_NEAR(v.x_m, fr.X(2.0 * i, lefts[w]), 1e-12);
      EXPECT_NEAR(v.z_m, fr.Z(2.0 * i, lefts[w]), 1e-12);
      EXPECT_EQ(v.offset_m, (w == 1 || w == 2) ? 1.5 : 0.0);
      EXPECT_NEAR(OffsetAt(b, v.x_m, v.z_m), v.offset_m, 1e-9);
    }
  }
  EXPECT_THROW(b.Vertex(11, 0), std::out_of_range);
  EXPECT_THROW(b.Vertex(0, 4), std::out_of_range);
}

TEST(Berm, BoundsAndMayCoverFollowTheRotatedFootprint) {
  auto f = Make(FeatureParams::Berm(30, 30, kPi / 4, 40, 4, 1));
  const Rect b = f->Bounds();
  // Footprint corners: along [-4/3, 40 + 4/3], left [-2, 2].
  const Frame fr{30, 30, kPi / 4};
  const double run = 4.0 / 3.0;
  for (double along : {-run, 40 + run}) {
    for (double left : {-2.0, 2.0}) {
      EXPECT_TRUE(b.Expanded(1e-9).Contains(fr.X(along, left), fr.Z(along, left)));
    }
  }
  EXPECT_NEAR(b.min_x, fr.X(-run, 2), 1e-9);
  EXPECT_NEAR(b.max_x, fr.X(40 + run, -2), 1e-9);
  // A corner of the box far from the diagonal strip.
  EXPECT_TRUE(b.Intersects({55, 30, 58, 33}));
  EXPECT_FALSE(f->MayCover({55, 30, 58, 33}));
  EXPECT_TRUE(f->MayCover({44, 44, 45, 45}));
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> pos(25, 65), size(0.01, 2);
  int covered_count = 0;
  for (int n = 0; n < 4000; ++n) {
    const double x = pos(rng), z = pos(rng), w = size(rng), h = size(rng);
    bool covered = false;
    for (double sx : {0.0, 0.5, 1.0}) {
      for (double sz : {0.0, 0.5, 1.0}) covered |= f->Covers(x + sx * w, z + sz * h);
    }
    if (covered) {
      ++covered_count;
      EXPECT_TRUE(f->MayCover({x, z, x + w, z + h})) << x << "," << z;
    }
  }
  EXPECT_GT(covered_count, 100);
}

TEST(Berm, ParamsRebuildTheSameBermAndMaterialResolvesFromTheGround) {
  HeightGrid ground = Ground();
  ground.set_soil(ground.SquareAt(10.5, 10.2), ground.HalfAt(10.5, 10.2), Material::kMud);
  const FeatureParams p = FeatureParams::Berm(10.5, 10.2, 0.25, 30, 5, 2);
  auto f = Make(p, ground);
  EXPECT_EQ(f->params(), p);
  EXPECT_EQ(f->material(), Material::kMud);
  auto concrete =
      Make(FeatureParams::Berm(10.5, 10.2, 0.25, 30, 5, 2, Material::kConcrete), ground);
  EXPECT_EQ(concrete->material(), Material::kConcrete);
  EXPECT_EQ(concrete->params().material, Material::kConcrete);
}

TEST(Berm, BadParametersAreRefusedWithTheValue) {
  const HeightGrid ground = Ground();
  auto refused = [&](const FeatureParams& p, const std::string& needle) {
    auto made = MakeBerm(kId, p, ground);
    ASSERT_FALSE(made.ok());
    EXPECT_NE(made.error().message.find(needle), std::string::npos) << made.error().message;
  };
  FeatureParams p = FeatureParams::Berm(50, 50, 0, 10, 3, 1);
  p.height_m[1] = 4;
  refused(p, "height_m[1]");
  refused(FeatureParams::Berm(50, 50, 0, 0, 3, 1), "length");
  refused(FeatureParams::Berm(50, 50, 0, 10, -3, 1), "-3");
  refused(FeatureParams::Berm(50, 50, 0, 10, 3, 51), "51");
  refused(FeatureParams::Berm(50, -1, 0, 10, 3, 1), "off the terrain");
  refused(FeatureParams::Crater(50, 50, 3), "a berm maker given a crater");
}

TEST(BermBreach, LeavesTwoShorterBermsAndABareGap) {
  const FeatureParams p = FeatureParams::Berm(10, 20, 0.4, 60, 6, 2, Material::kRock);
  auto original = Make(p);
  auto pieces = BreachBerm(p, 25, 8);
  ASSERT_TRUE(pieces.ok()) << pieces.error().message;
  ASSERT_EQ(pieces.value().size(), 2u);
  const FeatureParams& a = pieces.value()[0];
  const FeatureParams& b = pieces.value()[1];
  // Slope run 2: the first crest ends 2 m before the gap (at 19), the second starts 2 m after it
  // (at 31).
  EXPECT_DOUBLE_EQ(a.length_m[0], 19.0);
  EXPECT_EQ(a.x_m, p.x_m);
  EXPECT_EQ(a.z_m, p.z_m);
  const Frame fr{10, 20, 0.4};
  EXPECT_NEAR(b.x_m, fr.X(31, 0), 1e-12);
  EXPECT_NEAR(b.z_m, fr.Z(31, 0), 1e-12);
  EXPECT_NEAR(b.length_m[0], 29.0, 1e-12);
  for (const auto& q : {a, b}) {
    EXPECT_EQ(q.direction_rad, p.direction_rad);
    EXPECT_EQ(q.width_m, p.width_m);
    EXPECT_EQ(q.height_m, p.height_m);
    EXPECT_EQ(q.material, p.material);
  }
  auto fa = Make(a);
  auto fb = Make(b);
  for (double along = -3; along <= 63; along += 0.05) {
    for (double left : {0.0, 1.5, -2.7}) {
      const double x = fr.X(along, left), z = fr.Z(along, left);
      const double oa = fa->OffsetAboveGround(x, z).value_or(0.0);
      const double ob = fb->OffsetAboveGround(x, z).value_or(0.0);
      const double joined = std::max(oa, ob);
      if (along > 21 + 1e-9 && along < 29 - 1e-9) {
        EXPECT_EQ(joined, 0.0) << along;  // the gap is bare ground
        EXPECT_FALSE(fa->Covers(x, z));
        EXPECT_FALSE(fb->Covers(x, z));
      } else if (along < 19 || along > 31) {
        EXPECT_NEAR(joined, original->OffsetAboveGround(x, z).value_or(0.0), 1e-9) << along;
      }
    }
  }
}

TEST(BermBreach, NearAnEndLeavesOneOrNoBerm) {
  const FeatureParams p = FeatureParams::Berm(10, 20, 0, 30, 6, 2);
  auto near_start = BreachBerm(p, 2, 4);  // first crest would be 2 - 2 - 2 < 0
  ASSERT_TRUE(near_start.ok());
  ASSERT_EQ(near_start.value().size(), 1u);
  EXPECT_DOUBLE_EQ(near_start.value()[0].x_m, 10 + 6.0);
  EXPECT_DOUBLE_EQ(near_start.value()[0].length_m[0], 24.0);
  auto near_end = BreachBerm(p, 30, 2);
  ASSERT_TRUE(near_end.ok());
  ASSERT_EQ(near_end.value().size(), 1u);
  EXPECT_DOUBLE_EQ(near_end.value()[0].length_m[0], 27.0);
  auto all = BreachBerm(p, 15, 40);
  ASSERT_TRUE(all.ok());
  EXPECT_TRUE(all.value().empty());
}

TEST(BermBreach, APieceShorterThanTheSmallestFeatureIsDropped) {
  // Width 6: each end piece runs 2 m. A gap centred at 2 + 2 + 0.005 m leaves a 5 mm crest
  // before it, below kMinFeatureSizeM: no berm, so the breach leaves only the far piece.
  const FeatureParams p = FeatureParams::Berm(10, 20, 0, 30, 6, 2);
  const double centre_m = 2.0 + 2.0 + 0.5 * kMinFeatureSizeM;
  auto pieces = BreachBerm(p, centre_m, 4);
  ASSERT_TRUE(pieces.ok()) << pieces.error().message;
  ASSERT_EQ(pieces.value().size(), 1u);
  EXPECT_DOUBLE_EQ(pieces.value()[0].length_m[0], 30 - (centre_m + 2 + 2));
  for (const FeatureParams& piece : pieces.value()) EXPECT_TRUE(ValidateFeatureParams(piece).ok());
  // Twice the minimum (as computed: 4.02 - 2 - 2 is not exactly 0.02) stays.
  pieces = BreachBerm(p, 2.0 + 2.0 + 2 * kMinFeatureSizeM, 4);
  ASSERT_TRUE(pieces.ok());
  ASSERT_EQ(pieces.value().size(), 2u);
  EXPECT_NEAR(pieces.value()[0].length_m[0], 2 * kMinFeatureSizeM, 1e-12);
}

TEST(BermBreach, GapsOffTheBermAndBadInputAreRefused) {
  const FeatureParams p = FeatureParams::Berm(10, 20, 0, 30, 6, 2);
  auto expect_refused = [](const Result<std::vector<FeatureParams>>& r, const std::string& needle) {
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find(needle), std::string::npos) << r.error().message;
  };
  expect_refused(BreachBerm(p, 30.5, 2), "30.5");
  expect_refused(BreachBerm(p, -1, 2), "-1");
  expect_refused(BreachBerm(p, NAN, 2), "nan");
  expect_refused(BreachBerm(p, 10, 0), "gap width 0");
  expect_refused(BreachBerm(p, 10, INFINITY), "inf");
  expect_refused(BreachBerm(FeatureParams::Crater(10, 10, 3), 1, 1), "crater");
  FeatureParams bad = p;
  bad.width_m = -1;
  expect_refused(BreachBerm(bad, 10, 2), "width");
}

TEST(BermBreach, PiecesOfABermKeepItsResolvedMaterial) {
  HeightGrid ground = Ground();
  ground.set_soil(ground.SquareAt(10, 20), ground.HalfAt(10, 20), Material::kSand);
  auto f = Make(FeatureParams::Berm(10, 20, 0, 60, 6, 2), ground);
  auto pieces = BreachBerm(AsBerm(f), 30, 4);
  ASSERT_TRUE(pieces.ok());
  ASSERT_EQ(pieces.value().size(), 2u);
  for (const auto& q : pieces.value()) EXPECT_EQ(q.material, Material::kSand);
  // From params alone the material stays "from the ground".
  auto from_params = BreachBerm(f->params(), 30, 4);
  ASSERT_TRUE(from_params.ok());
  for (const auto& q : from_params.value()) EXPECT_EQ(q.material, Material::kFromGround);
}

TEST(Emplacement, ThreeBermsFormAUWhoseCrestEndsMeet) {
  for (double facing : {0.0, 1.0, -2.2}) {
    const EmplacementSpec spec{.centre_x_m = 50,
                               .centre_z_m = 50,
                               .facing_rad = facing,
                               .size_m = 20,
                               .width_m = 4,
                               .height_m = 1.5,
                               .material = Material::kDirt};
    auto made = EmplacementBerms(spec);
    ASSERT_TRUE(made.ok()) << made.error().message;
    std::vector<std::unique_ptr<Feature>> berms;
    for (const auto& p : made.value()) {
      EXPECT_EQ(p.length_m[0], 20);
      EXPECT_EQ(p.width_m, 4);
      EXPECT_EQ(p.height_m[0], 1.5);
      EXPECT_EQ(p.material, Material::kDirt);
      berms.push_back(Make(p));
    }
    const Frame c{50, 50, facing};  // along = forward, left = left
    auto crest_end = [](const Feature& f) {
      const BermVertex a = static_cast<const Berm&>(f).Vertex(kBermLengthLines - 1, 1);
      const BermVertex b = static_cast<const Berm&>(f).Vertex(kBermLengthLines - 1, 2);
      return std::pair((a.x_m + b.x_m) / 2, (a.z_m + b.z_m) / 2);
    };
    // Front: from front-right to front-left. Left and right run back from the front corners.
    const auto& front = made.value()[0];
    const auto& left = made.value()[1];
    const auto& right = made.value()[2];
    EXPECT_NEAR(front.x_m, c.X(10, -10), 1e-9);
    EXPECT_NEAR(front.z_m, c.Z(10, -10), 1e-9);
    EXPECT_NEAR(crest_end(*berms[0]).first, c.X(10, 10), 1e-9);
    EXPECT_NEAR(crest_end(*berms[0]).second, c.Z(10, 10), 1e-9);
    EXPECT_NEAR(left.x_m, c.X(10, 10), 1e-9);
    EXPECT_NEAR(left.z_m, c.Z(10, 10), 1e-9);
    EXPECT_NEAR(crest_end(*berms[1]).first, c.X(-10, 10), 1e-9);
    EXPECT_NEAR(right.x_m, c.X(10, -10), 1e-9);
    EXPECT_NEAR(crest_end(*berms[2]).second, c.Z(-10, -10), 1e-9);
    // Walking the crest back-right -> front-right -> front-left -> back-left never dips.
    const std::array<std::pair<double, double>, 4> path = {
        {{-10, -10}, {10, -10}, {10, 10}, {-10, 10}}};
    for (size_t leg = 0; leg + 1 < path.size(); ++leg) {
      for (double s = 0; s <= 1.0; s += 0.01) {
        const double along = path[leg].first + s * (path[leg + 1].first - path[leg].first);
        const double lft = path[leg].second + s * (path[leg + 1].second - path[leg].second);
        double highest = 0.0;
        for (const auto& f : berms) {
          highest = std::max(highest,
                             f->OffsetAboveGround(c.X(along, lft), c.Z(along, lft)).value_or(0.0));
        }
        EXPECT_NEAR(highest, 1.5, 1e-9) << "leg " << leg << " s " << s;
      }
    }
    // The open rear and the inside are bare.
    for (const auto& f : berms) {
      EXPECT_FALSE(f->Covers(c.X(0, 0), c.Z(0, 0)));
      EXPECT_FALSE(f->Covers(c.X(-11, 0), c.Z(-11, 0)));
    }
  }
}

TEST(Emplacement, BadSizesAreRefused) {
  auto r = EmplacementBerms({50, 50, 0, 0, 4, 1.5, Material::kDirt});
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("length"), std::string::npos) << r.error().message;
  auto h = EmplacementBerms({50, 50, 0, 10, 4, -1, Material::kDirt});
  ASSERT_FALSE(h.ok());
  EXPECT_NE(h.error().message.find("height"), std::string::npos) << h.error().message;
  EXPECT_FALSE(EmplacementBerms({50, 50, NAN, 10, 4, 1, Material::kDirt}).ok());
}

}  // namespace
}  // namespace dt
