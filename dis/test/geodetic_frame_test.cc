// Local east/north/up metres against WGS-84 geocentric, and attitudes against DIS Euler angles.
#include "dis/geodetic_frame.h"

#include <gtest/gtest.h>
#include <GeographicLib/Geocentric.hpp>
#include <GeographicLib/LocalCartesian.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <stdexcept>
#include <vector>

namespace dt::dis {
namespace {

constexpr double kPi = std::numbers::pi;

double Distance(const WorldCoordinates& a, const WorldCoordinates& b) {
  return std::sqrt((a.x - b.x) * (a.x - b.x) + (a.y - b.y) * (a.y - b.y) +
                   (a.z - b.z) * (a.z - b.z));
}

// Angle difference folded into (-pi, pi].
double AngleDiff(double a, double b) { return std::remainder(a - b, 2.0 * kPi); }

const GeodeticOrigin kOrigins[] = {{0.0, 0.0, 0.0},
                                   {36.6, -121.9, 20.0},
                                   {-33.9, 151.2, 100.0},
                                   {60.2, 24.9, -5.0},
                                   {89.0, 45.0, 0.0}};

TEST(GeodeticFrame, OriginAtTheEquatorAndPrimeMeridianIsOnTheXAxis) {
  const GeodeticFrame frame({0.0, 0.0, 0.0});
  const WorldCoordinates c = frame.ToGeocentric({0, 0, 0});
  EXPECT_NEAR(c.x, 6378137.0, 1e-6);  // WGS-84 equatorial radius
  EXPECT_NEAR(c.y, 0.0, 1e-6);
  EXPECT_NEAR(c.z, 0.0, 1e-6);
  // There east is +Y, north +Z, up +X.
  const WorldCoordinates east = frame.ToGeocentric({1000, 0, 0});
  EXPECT_NEAR(east.y, 1000.0, 1e-6);
  const WorldCoordinates north = frame.ToGeocentric({0, 0, 1000});
  EXPECT_NEAR(north.z, 1000.0, 1e-6);
  const WorldCoordinates up = frame.ToGeocentric({0, 1000, 0});
  EXPECT_NEAR(up.x, 6378137.0 + 1000.0, 1e-6);
}

TEST(GeodeticFrame, OriginAtThePoleIsOnTheZAxis) {
  const GeodeticFrame frame({90.0, 0.0, 0.0});
  const WorldCoordinates c = frame.ToGeocentric({0, 0, 0});
  EXPECT_NEAR(c.z, 6356752.314245, 1e-5);  // WGS-84 polar radius
  EXPECT_NEAR(std::hypot(c.x, c.y), 0.0, 1e-6);
}

TEST(GeodeticFrame, OriginMapsToItsGeocentricPointAndNeighboursToTheirDistance) {
  for (const GeodeticOrigin& o : kOrigins) {
    const GeodeticFrame frame(o);
    double x, y, z;
    GeographicLib::Geocentric::WGS84().Forward(o.latitude_deg, o.longitude_deg, o.height_m, x, y,
                                               z);
    const WorldCoordinates at_origin = frame.ToGeocentric({0, 0, 0});
    EXPECT_NEAR(Distance(at_origin, {x, y, z}), 0.0, 1e-6);
    EXPECT_NEAR(Distance(frame.ToGeocentric({1000, 0, 0}), at_origin), 1000.0, 1e-6);
    EXPECT_NEAR(Distance(frame.ToGeocentric({0, 0, -1000}), at_origin), 1000.0, 1e-6);
    EXPECT_NEAR(Distance(frame.ToGeocentric({300, 400, 0}), at_origin), 500.0, 1e-6);
  }
}

TEST(GeodeticFrame, AgreesWithGeographicLibsLocalCartesian) {
  for (const GeodeticOrigin& o : kOrigins) {
    const GeodeticFrame frame(o);
    const GeographicLib::LocalCartesian enu(o.latitude_deg, o.longitude_deg, o.height_m);
    const LocalPoint p{1234.5, 87.25, -4321.0};  // x east, y up, z north
    double lat, lon, h;
    enu.Reverse(p.x_m, p.z_m, p.y_m, lat, lon, h);
    double x, y, z;
    GeographicLib::Geocentric::WGS84().Forward(lat, lon, h, x, y, z);
    EXPECT_NEAR(Distance(frame.ToGeocentric(p), {x, y, z}), 0.0, 1e-6);
  }
}

TEST(GeodeticFrame, A1000MetreStepNorthRaisesTheLatitude) {
  const GeodeticFrame frame({45.0, 7.0, 0.0});
  const WorldCoordinates c = frame.ToGeocentric({0, 0, 1000});
  double lat, lon, h;
  GeographicLib::Geocentric::WGS84().Reverse(c.x, c.y, c.z, lat, lon, h);
  EXPECT_GT(lat, 45.0);
  EXPECT_NEAR(lat - 45.0, 1000.0 / 111132.0, 1e-4);  // about 111.1 km per degree at 45 deg
  EXPECT_NEAR(lon, 7.0, 1e-9);
}

TEST(GeodeticFrame, PositionsRoundTripToAMillimetre) {
  std::mt19937 rng(12);
  std::uniform_real_distribution<double> across(-50000.0, 50000.0);
  std::uniform_real_distribution<double> height(-500.0, 3000.0);
  for (const GeodeticOrigin& o : kOrigins) {
    const GeodeticFrame frame(o);
    for (int i = 0; i < 200; ++i) {
      const LocalPoint p{across(rng), height(rng), across(rng)};
      const LocalPoint back = frame.FromGeocentric(frame.ToGeocentric(p));
      EXPECT_NEAR(back.x_m, p.x_m, 1e-3);
      EXPECT_NEAR(back.y_m, p.y_m, 1e-3);
      EXPECT_NEAR(back.z_m, p.z_m, 1e-3);
    }
  }
}

TEST(GeodeticFrame, LevelHeadingNorthAtTheEquatorIsThetaMinus90) {
  // The textbook case: at latitude 0, longitude 0, a level entity facing north points along +Z.
  const GeodeticFrame frame({0.0, 0.0, 0.0});
  const auto a = frame.ToDisAnglesRad({kPi / 2, 0.0, 0.0});
  EXPECT_NEAR(a[0], 0.0, 1e-9);
  EXPECT_NEAR(a[1], -kPi / 2, 1e-9);
  EXPECT_NEAR(a[2], 0.0, 1e-9);
}

TEST(GeodeticFrame, LevelHeadingEastAtTheEquatorAndItsRoll) {
  const GeodeticFrame frame({0.0, 0.0, 0.0});
  // Facing east (+Y), right is south (-Z), down is -X: psi 90 deg, theta 0, phi -90 deg.
  auto a = frame.ToDisAnglesRad({0.0, 0.0, 0.0});
  EXPECT_NEAR(a[0], kPi / 2, 1e-9);
  EXPECT_NEAR(a[1], 0.0, 1e-9);
  EXPECT_NEAR(a[2], -kPi / 2, 1e-9);
  // Right side down (positive roll) adds to phi; nose up (positive pitch) tilts forward to +X.
  a = frame.ToDisAnglesRad({0.0, 0.0, 0.1});
  EXPECT_NEAR(a[2], -kPi / 2 + 0.1, 1e-9);
  a = frame.ToDisAnglesRad({0.0, 0.2, 0.0});
  const double psi = a[0], theta = a[1];
  EXPECT_NEAR(std::cos(psi) * std::cos(theta), std::sin(0.2), 1e-9);  // forward's X component
}

TEST(GeodeticFrame, AttitudesRoundTripToAMicroradian) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> heading(-kPi + 1e-3, kPi);
  std::uniform_real_distribution<double> tilt(-1.4, 1.4);
  std::uniform_real_distribution<double> roll(-kPi + 1e-3, kPi);
  for (const GeodeticOrigin& o : kOrigins) {
    const GeodeticFrame frame(o);
    for (int i = 0; i < 200; ++i) {
      const LocalAttitude a{heading(rng), tilt(rng), roll(rng)};
      const auto e = frame.ToDisAnglesRad(a);
      const LocalAttitude back = frame.FromDisAnglesRad(e[0], e[1], e[2]);
      EXPECT_NEAR(AngleDiff(back.heading_rad, a.heading_rad), 0.0, 1e-6);
      EXPECT_NEAR(back.pitch_rad - a.pitch_rad, 0.0, 1e-6);
      EXPECT_NEAR(AngleDiff(back.roll_rad, a.roll_rad), 0.0, 1e-6);
      // Through the PDU's floats: within float rounding of angles up to pi.
      const LocalAttitude via_float = frame.FromDisOrientation(frame.ToDisOrientation(a));
      EXPECT_NEAR(AngleDiff(via_float.heading_rad, a.heading_rad), 0.0, 2e-6);
      EXPECT_NEAR(via_float.pitch_rad - a.pitch_rad, 0.0, 2e-6);
      EXPECT_NEAR(AngleDiff(via_float.roll_rad, a.roll_rad), 0.0, 2e-6);
    }
  }
}

// The attitude from DIS angles as it was first written (the heading's sine and cosine taken of
// the angle, the ground length by hypot), to hold the cheaper form to it.
LocalAttitude FirstFormOfFromDisAngles(const GeodeticOrigin& o, double psi, double theta,
                                       double phi) {
  std::vector<double> m(9);
  double x, y, z;
  GeographicLib::Geocentric::WGS84().Forward(o.latitude_deg, o.longitude_deg, o.height_m, x, y, z,
                                             m);
  const double cps = std::cos(psi), sps = std::sin(psi);
  const double ct = std::cos(theta), st = std::sin(theta);
  const double cph = std::cos(phi), sph = std::sin(phi);
  const double fe[3] = {cps * ct, sps * ct, -st};
  const double re[3] = {cps * st * sph - sps * cph, sps * st * sph + cps * cph, ct * sph};
  double f[3], r[3];
  for (int i = 0; i < 3; ++i) {
    f[i] = m[i] * fe[0] + m[3 + i] * fe[1] + m[6 + i] * fe[2];
    r[i] = m[i] * re[0] + m[3 + i] * re[1] + m[6 + i] * re[2];
  }
  LocalAttitude a;
  a.pitch_rad = std::asin(std::clamp(f[2], -1.0, 1.0));
  a.heading_rad = std::atan2(f[1], f[0]);
  const double lr[3] = {std::sin(a.heading_rad), -std::cos(a.heading_rad), 0.0};
  const double ld[3] = {f[1] * lr[2] - f[2] * lr[1], f[2] * lr[0] - f[0] * lr[2],
                        f[0] * lr[1] - f[1] * lr[0]};
  a.roll_rad = std::atan2(r[0] * ld[0] + r[1] * ld[1] + r[2] * ld[2],
                          r[0] * lr[0] + r[1] * lr[1] + r[2] * lr[2]);
  return a;
}

TEST(GeodeticFrame, FromDisAnglesAgreesWithItsFirstFormToAPicoradian) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> angle(-kPi, kPi);
  std::uniform_real_distribution<double> tilt(-1.5, 1.5);
  for (const GeodeticOrigin& o : kOrigins) {
    const GeodeticFrame frame(o);
    for (int i = 0; i < 2000; ++i) {
      const double psi = angle(rng), theta = tilt(rng), phi = angle(rng);
      const LocalAttitude now = frame.FromDisAnglesRad(psi, theta, phi);
      const LocalAttitude first = FirstFormOfFromDisAngles(o, psi, theta, phi);
      if (std::abs(first.pitch_rad) > 1.5) continue;  // near vertical, roll is ill-conditioned
      EXPECT_NEAR(AngleDiff(now.heading_rad, first.heading_rad), 0.0, 1e-12);
      EXPECT_NEAR(now.pitch_rad - first.pitch_rad, 0.0, 1e-12);
      EXPECT_NEAR(AngleDiff(now.roll_rad, first.roll_rad), 0.0, 1e-12);
    }
  }
}

TEST(GeodeticFrame, VectorsRotateWithoutTranslation) {
  const GeodeticFrame frame({36.6, -121.9, 20.0});
  const LocalPoint v{3.0, -1.0, 4.0};
  const Vector3F g = frame.VectorToGeocentric(v);
  EXPECT_NEAR(std::sqrt(double{g.x} * g.x + double{g.y} * g.y + double{g.z} * g.z), std::sqrt(26.0),
              1e-5);
  const LocalPoint back = frame.VectorFromGeocentric(g);
  EXPECT_NEAR(back.x_m, 3.0, 1e-5);
  EXPECT_NEAR(back.y_m, -1.0, 1e-5);
  EXPECT_NEAR(back.z_m, 4.0, 1e-5);
}

TEST(GeodeticFrame, RefusesOriginsOutOfRange) {
  EXPECT_THROW(GeodeticFrame({90.5, 0, 0}), std::invalid_argument);
  EXPECT_THROW(GeodeticFrame({0, -180.5, 0}), std::invalid_argument);
  EXPECT_THROW(GeodeticFrame({0, 0, std::nan("")}), std::invalid_argument);
  EXPECT_THROW(GeodeticFrame({0, 0, 2e5}), std::invalid_argument);
  EXPECT_NO_THROW(GeodeticFrame({-90, 180, -100}));
}

}  // namespace
}  // namespace dt::dis
