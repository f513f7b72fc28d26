// A feature placed at a known latitude and longitude on ground from an elevation file goes out
// on DIS within 1 m of that point, and comes back to the same terrain position (UTM and lat/lon
// files). A vehicle heading grid north on a UTM ground is reported at the true bearing of grid
// north there (the meridian convergence).
#include <cmath>
#include <filesystem>
#include <numbers>

#include <gtest/gtest.h>
#include <GeographicLib/Geocentric.hpp>
#include <GeographicLib/UTMUPS.hpp>

#include "dis/dis_codec.h"
#include "dis/feature_mapping.h"
#include "dis/vehicle_mapping.h"
#include "geo/elevation_loader.h"
#include "geo/test/test_rasters.h"

namespace dt::dis {
namespace {

constexpr PduContext kContext{5, 0x100};

struct Case {
  int epsg;
  std::array<double, 6> geotransform;
  double latitude_deg;  // the feature's place, inside the file
  double longitude_deg;
};

class RealGroundDisTest : public ::testing::TestWithParam<Case> {
 protected:
  void SetUp() override { dir_ = dt::testing::FreshTestDir("real_ground_dis_test"); }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::filesystem::path dir_;
};

TEST_P(RealGroundDisTest, AFeatureAtAKnownLatLonIsThereOnDis) {
  const Case& c = GetParam();
  dt::testing::TestRaster r;
  r.epsg = c.epsg;
  r.cols = 200;
  r.rows = 150;
  r.geotransform = c.geotransform;
  r.surface = [](double, double) { return 250.0; };
  dt::testing::WriteTestRaster(dir_ / "g.tif", r);
  const ElevationLayout layout = ProbeElevation({.file = dir_ / "g.tif"});
  const GeodeticPoint o = layout.georeference->origin();
  const GeodeticFrame frame({o.latitude_deg, o.longitude_deg, o.height_m}, layout.georeference);

  double want_lat = c.latitude_deg, want_lon = c.longitude_deg;
  if (c.epsg == 32633) {
    // Placed by easting and northing, read back by GeographicLib's own UTM.
    GeographicLib::UTMUPS::Reverse(33, true, 501200.0, 5200900.0, want_lat, want_lon);
  }
  const std::array<double, 2> xz = layout.georeference->FromGeodetic(want_lat, want_lon);
  if (c.epsg == 32633) {
    EXPECT_NEAR(xz[0], 1200.0 - 5.0, 1e-3);  // terrain (0, 0) is the first pixel's centre
    EXPECT_NEAR(xz[1], 900.0 - 5.0, 1e-3);
  }
  ASSERT_GT(xz[0], 0.0);
  ASSERT_GT(xz[1], 0.0);
  const auto pdu =
      FeatureToDis({3, 4, 17}, FeatureParams::Crater(xz[0], xz[1], 5.0), 250.0, 1, frame, kContext);
  ASSERT_TRUE(pdu.ok()) << pdu.error().message;
  const std::vector<uint8_t> bytes =
      std::visit([](const auto& p) { return Encode(p); }, pdu.value());
  const DecodeResult decoded = DecodePdu(bytes, kContext.exercise_id);
  ASSERT_TRUE(decoded.ok());
  const auto& point = std::get<PointObjectStatePdu>(decoded.pdu());
  double lat = 0, lon = 0, h = 0;
  GeographicLib::Geocentric::WGS84().Reverse(point.location.x, point.location.y, point.location.z,
                                             lat, lon, h);
  EXPECT_LT(GeocentricDistanceM({lat, lon, h}, {want_lat, want_lon, 250.0}), 1.0)
      << lat << " " << lon << " " << h;
  EXPECT_NEAR(h, 250.0, 1e-3);

  const auto back = FeatureFromDisPdu(point, frame);
  ASSERT_TRUE(back.ok()) << back.error().message;
  EXPECT_NEAR(back.value().params.x_m, xz[0], 1e-3);
  EXPECT_NEAR(back.value().params.z_m, xz[1], 1e-3);
}

// 200 km east of UTM 33N's central meridian at 47 N the convergence is about 1.9 deg: an
// orientation kept in the origin's east/north axes would be off by all of it.
TEST(RealGroundDisOrientation, GridNorthIsReportedAtItsTrueBearing) {
  const std::filesystem::path dir = dt::testing::FreshTestDir("real_ground_dis_orientation");
  dt::testing::TestRaster r;
  r.epsg = 32633;
  r.cols = 200;
  r.rows = 150;
  r.geotransform = {700000.0, 10, 0, 5201500.0, 0, -10};
  r.surface = [](double, double) { return 250.0; };
  dt::testing::WriteTestRaster(dir / "g.tif", r);
  const ElevationLayout layout = ProbeElevation({.file = dir / "g.tif"});
  std::filesystem::remove_all(dir);
  const GeodeticPoint o = layout.georeference->origin();
  const GeodeticFrame frame({o.latitude_deg, o.longitude_deg, o.height_m}, layout.georeference);

  VehiclePose pose;
  pose.entity_id = {3, 4, 17};
  pose.marking = "tank-17";
  pose.position_m = {1500.0, 250.0, 1000.0};
  pose.attitude.heading_rad = std::numbers::pi / 2;  // +z: grid north
  pose.velocity_mps = {0.0, 0.0, 10.0};              // 10 m/s grid north
  const auto pdu = ToEntityState(pose, frame, kContext);
  ASSERT_TRUE(pdu.ok()) << pdu.error().message;
  const DecodeResult decoded = DecodePdu(Encode(pdu.value()), kContext.exercise_id);
  ASSERT_TRUE(decoded.ok());
  const auto& es = std::get<EntityStatePdu>(decoded.pdu());

  // GeographicLib's own UTM: the convergence gamma at the entity (grid north's bearing,
  // clockwise from true north).
  double lat = 0, lon = 0, h = 0;
  std::vector<double> m(9);
  GeographicLib::Geocentric::WGS84().Reverse(es.location.x, es.location.y, es.location.z, lat, lon,
                                             h, m);
  int zone = 0;
  bool northp = false;
  double easting = 0, northing = 0, gamma_deg = 0, k = 0;
  GeographicLib::UTMUPS::Forward(lat, lon, zone, northp, easting, northing, gamma_deg, k, 33);
  const double gamma_rad = gamma_deg * std::numbers::pi / 180.0;
  ASSERT_GT(std::abs(gamma_rad), 0.03);  // large enough that the test tells
  EXPECT_NEAR(frame.GridConvergenceRad(pose.position_m), gamma_rad, 1e-4);

  // The body's forward axis (the first column of Rz(psi) Ry(theta)) in east/north/up there.
  const double psi = es.orientation.psi, theta = es.orientation.theta;
  const double f[3] = {std::cos(psi) * std::cos(theta), std::sin(psi) * std::cos(theta),
                       -std::sin(theta)};
  const double east = m[0] * f[0] + m[3] * f[1] + m[6] * f[2];
  const double north = m[1] * f[0] + m[4] * f[1] + m[7] * f[2];
  const double up = m[2] * f[0] + m[5] * f[1] + m[8] * f[2];
  // True heading counter-clockwise from true north is -gamma; its bearing is gamma.
  EXPECT_NEAR(std::atan2(east, north), gamma_rad, 0.01);
  EXPECT_NEAR(std::atan2(east, north), gamma_rad, 1e-4) << "tighter than the goal";
  EXPECT_NEAR(up, 0.0, 1e-5) << "level on the ellipsoid there";
  // The velocity goes the same way.
  const double ve =
      m[0] * es.linear_velocity.x + m[3] * es.linear_velocity.y + m[6] * es.linear_velocity.z;
  const double vn =
      m[1] * es.linear_velocity.x + m[4] * es.linear_velocity.y + m[7] * es.linear_velocity.z;
  EXPECT_NEAR(std::atan2(ve, vn), gamma_rad, 1e-4);

  // And back: grid north again.
  const auto back = FromEntityState(es, frame);
  ASSERT_TRUE(back.ok()) << back.error().message;
  EXPECT_NEAR(back.value().attitude.heading_rad, std::numbers::pi / 2, 1e-5);
  EXPECT_NEAR(back.value().velocity_mps.z_m, 10.0, 1e-4);
  EXPECT_NEAR(back.value().velocity_mps.x_m, 0.0, 1e-4);
}

INSTANTIATE_TEST_SUITE_P(
    UtmAndLatLon, RealGroundDisTest,
    ::testing::Values(
        // UTM 33N, 10 m pixels: 2 km x 1.5 km; the feature 1.2 km east, 0.9 km north of the corner.
        Case{32633, {500000.0, 10, 0, 5201500.0, 0, -10}, 0.0, 0.0},
        // WGS-84 lat/lon, 0.0001 deg pixels near 47 N 8 E.
        Case{4326, {8.0, 0.0001, 0, 47.015, 0, -0.0001}, 47.009, 8.013}));

}  // namespace
}  // namespace dt::dis
