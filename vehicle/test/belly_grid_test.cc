// Unit tests of the belly grid: its layout, and that marking under bounds misses no point inside.
#include "vehicle/belly_grid.h"

#include <cmath>
#include <numbers>
#include <random>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

namespace dt::test {
namespace {

using Eigen::Matrix3d;
using Eigen::Vector3d;

// A tank's footprint: 7 m by 3.6 m, the bottom 0.45 m under the centre of mass.
BellyGrid TankGrid() {
  BellyGrid g(7.0, 3.6, 0.5, -0.45);
  int contact = 0;
  for (int s = 0; s < g.stations(); ++s) {
    for (int l = 0; l < g.lines(); ++l) {
      if (!g.OnCentreLine(l)) g.SetContact(s, l, contact++);
    }
  }
  return g;
}

int ContactCount(const BellyGrid& g) {
  int n = 0;
  for (int s = 0; s < g.stations(); ++s) {
    for (int l = 0; l < g.lines(); ++l) n += g.ContactAt(s, l) >= 0 ? 1 : 0;
  }
  return n;
}

Matrix3d Attitude(double heading_rad, double pitch_rad, double roll_rad) {
  return (Eigen::AngleAxisd(-heading_rad, Vector3d::UnitY()) *
          Eigen::AngleAxisd(pitch_rad, Vector3d::UnitZ()) *
          Eigen::AngleAxisd(-roll_rad, Vector3d::UnitX()))
      .toRotationMatrix();
}

TEST(BellyGrid, SpacesPointsAtMostTheSpacingApartAndLeavesOutTheCentreLine) {
  const BellyGrid g = TankGrid();
  EXPECT_EQ(g.stations(), 15);
  EXPECT_EQ(g.lines(), 9);
  EXPECT_LE(g.station_step_m(), 0.5);
  EXPECT_LE(g.line_step_m(), 0.5);
  EXPECT_TRUE(g.OnCentreLine(4));
  EXPECT_EQ(g.ContactAt(0, 4), -1);
  EXPECT_EQ(ContactCount(g), 15 * 8);
  EXPECT_EQ(g.Body(0, 0), Vector3d(-3.5, -0.45, -1.8));
  EXPECT_EQ(g.Body(14, 8), Vector3d(3.5, -0.45, 1.8));
  EXPECT_EQ(g.ContactAt(-1, 0), -1);
  EXPECT_EQ(g.ContactAt(0, 9), -1);
}

// Random attitudes (headings along the axes among them, where a line's stations share a plan
// coordinate) and rectangles around the footprint: every point that x + R * Body puts inside a
// rectangle is marked, and a rectangle far smaller than the footprint marks far fewer points
// than the grid has.
TEST(BellyGrid, MarksEveryPointInsideTheBoundsAndFewOthers) {
  const BellyGrid g = TankGrid();
  const int contacts = ContactCount(g);
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int inside_total = 0, marked_total = 0, small_cases = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    const double heading = trial % 4 == 0 ? (trial / 4 % 4) * std::numbers::pi / 2.0
                                          : 2.0 * std::numbers::pi * unit(rng);
    const double pitch = trial % 3 == 0 ? 0.0 : 0.6 * (unit(rng) - 0.5);
    const double roll = trial % 3 == 0 ? 0.0 : 0.6 * (unit(rng) - 0.5);
    const Matrix3d R = Attitude(heading, pitch, roll);
    const Vector3d x(40000.0 + 100.0 * unit(rng), 50.0, 20000.0 + 100.0 * unit(rng));
    const double size = trial % 2 == 0 ? 0.05 + 1.5 * unit(rng) : 1.0 + 8.0 * unit(rng);
    const double cx = x.x() + 10.0 * (unit(rng) - 0.5), cz = x.z() + 10.0 * (unit(rng) - 0.5);
    // Some rectangles end exactly on a grid point.
    const Vector3d corner = x + R * g.Body(trial % g.stations(), trial % g.lines());
    const Rect bounds = trial % 5 == 0
                            ? Rect{corner.x(), corner.z(), corner.x() + size, corner.z() + size}
                            : Rect{cx, cz, cx + size, cz + size};
    const NearEarthwork near[] = {{nullptr, bounds}};
    std::vector<uint8_t> marks(static_cast<size_t>(contacts), 0);
    g.MarkUnder(x, R, near, marks);
    int inside = 0, marked = 0;
    for (int s = 0; s < g.stations(); ++s) {
      for (int l = 0; l < g.lines(); ++l) {
        const int k = g.ContactAt(s, l);
        if (k < 0) continue;
        const Vector3d p = x + R * g.Body(s, l);
        const bool in = bounds.Contains(p.x(), p.z());
        const bool mark = marks[static_cast<size_t>(k)] != 0;
        ASSERT_TRUE(!in || mark) << "trial " << trial << " station " << s << " line " << l;
        inside += in ? 1 : 0;
        marked += mark ? 1 : 0;
      }
    }
    if (size < 1.0) {
      ++small_cases;
      inside_total += inside;
      marked_total += marked;
    }
  }
  // A rectangle under 1 m across holds a few points at most; the marks add a station each way.
  EXPECT_GT(inside_total, 0);
  EXPECT_LT(marked_total, small_cases * contacts / 10);
}

TEST(BellyGrid, MarksNothingForBoundsClearOfTheFootprint) {
  const BellyGrid g = TankGrid();
  std::vector<uint8_t> marks(static_cast<size_t>(ContactCount(g)), 0);
  const Vector3d x(500.0, 50.0, 500.0);
  const NearEarthwork near[] = {{nullptr, Rect{506.0, 490.0, 520.0, 510.0}},
                                {nullptr, Rect{490.0, 496.0, 510.0, 497.0}}};
  g.MarkUnder(x, Attitude(0.0, 0.0, 0.0), near, marks);
  for (uint8_t m : marks) EXPECT_EQ(m, 0);
}

}  // namespace
}  // namespace dt::test
