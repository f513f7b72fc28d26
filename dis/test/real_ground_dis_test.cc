// A feature placed at a known latitude and longitude on ground from an elevation file goes out
// on DIS within 1 m of that point, and comes back to the same terrain position (UTM and lat/lon
// files).
#include <cmath>
#include <filesystem>

#include <gtest/gtest.h>
#include <GeographicLib/Geocentric.hpp>
#include <GeographicLib/UTMUPS.hpp>

#include "dis/dis_codec.h"
#include "dis/feature_mapping.h"
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

INSTANTIATE_TEST_SUITE_P(
    UtmAndLatLon, RealGroundDisTest,
    ::testing::Values(
        // UTM 33N, 10 m pixels: 2 km x 1.5 km; the feature 1.2 km east, 0.9 km north of the corner.
        Case{32633, {500000.0, 10, 0, 5201500.0, 0, -10}, 0.0, 0.0},
        // WGS-84 lat/lon, 0.0001 deg pixels near 47 N 8 E.
        Case{4326, {8.0, 0.0001, 0, 47.015, 0, -0.0001}, 47.009, 8.013}));

}  // namespace
}  // namespace dt::dis
