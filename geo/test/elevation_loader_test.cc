// ProbeElevation and LoadElevation on analytic surfaces written as GeoTIFF (UTM and lat/lon) and
// DTED at test time: every post against the formula, windows, nodata, and the errors.
#include "geo/elevation_loader.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <numbers>

#include <gtest/gtest.h>
#include <GeographicLib/LocalCartesian.hpp>
#include <GeographicLib/UTMUPS.hpp>

#include "geo/test/test_rasters.h"

namespace dt {
namespace {

using testing::FreshTestDir;
using testing::TestRaster;
using testing::WriteTestRaster;

constexpr double kPi = std::numbers::pi;
// The UTM surface: zone 33N near 47 N 15 E, 10 m pixels, a wave of 400 m and 20 m amplitude on a
// slope.
constexpr double kE0 = 500000.0;
constexpr double kN0 = 5200000.0;
constexpr double kPixelM = 10.0;
constexpr double kWaveM = 400.0;
constexpr double kAmplitudeM = 20.0;

double UtmSurface(double e, double n) {
  return 100.0 +
         kAmplitudeM * std::sin(2 * kPi * (e - kE0) / kWaveM) *
             std::cos(2 * kPi * (n - kN0) / kWaveM) +
         0.01 * (e - kE0);
}

// Bilinear interpolation's bound for h-spaced samples: h^2 / 8 times the second derivatives along
// each axis, plus float rounding of the stored pixels.
double BilinearBound(double h, double second_derivative_max) {
  return h * h / 8.0 * 2.0 * second_derivative_max + 1e-3;
}
const double kUtmBoundM = BilinearBound(kPixelM, kAmplitudeM* std::pow(2 * kPi / kWaveM, 2));

class ElevationLoaderTest : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = FreshTestDir("geo_test"); }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  // 101 x 80 pixels: centres from (kE0 + 5, kN0 + 5) to (kE0 + 1005, kN0 + 795).
  std::filesystem::path WriteUtm(std::optional<double> nodata = std::nullopt,
                                 std::vector<std::pair<int, int>> holes = {}) {
    TestRaster r;
    r.epsg = 32633;
    r.cols = 101;
    r.rows = 80;
    r.geotransform = {kE0, kPixelM, 0, kN0 + 80 * kPixelM, 0, -kPixelM};
    r.surface = UtmSurface;
    r.nodata = nodata;
    r.holes = std::move(holes);
    const auto path = dir_ / "utm.tif";
    WriteTestRaster(path, r);
    return path;
  }

  std::filesystem::path dir_;
};

// The error text of f(), or "" if it threw nothing.
template <typename F>
std::string ErrorOf(F&& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

TEST_F(ElevationLoaderTest, UtmWholeFileAtItsSpacingIsThePixels) {
  ElevationSource s{.file = WriteUtm()};
  const ElevationLayout layout = ProbeElevation(s);
  EXPECT_TRUE(layout.local_is_file_crs);
  EXPECT_EQ(layout.posts_x, 101);
  EXPECT_EQ(layout.posts_z, 80);
  EXPECT_DOUBLE_EQ(layout.spacing_m, kPixelM);
  const HeightGrid g = LoadElevation(s, layout);
  for (int j = 0; j < g.posts_z(); ++j) {
    for (int i = 0; i < g.posts_x(); ++i) {
      ASSERT_NEAR(g.post(i, j), UtmSurface(kE0 + 5 + kPixelM * i, kN0 + 5 + kPixelM * j), 1e-4)
          << i << ", " << j;
    }
  }
  // Terrain (0, 0, 0) is the south-west pixel centre, on WGS-84 by GeographicLib's own UTM.
  double lat = 0, lon = 0;
  GeographicLib::UTMUPS::Reverse(33, true, kE0 + 5, kN0 + 5, lat, lon);
  const GeodeticPoint o = layout.georeference->origin();
  EXPECT_NEAR(o.latitude_deg, lat, 1e-8);
  EXPECT_NEAR(o.longitude_deg, lon, 1e-8);
  EXPECT_EQ(o.height_m, 0.0);
  const auto xz = layout.georeference->FromGeodetic(lat, lon);
  EXPECT_NEAR(xz[0], 0.0, 1e-3);
  EXPECT_NEAR(xz[1], 0.0, 1e-3);
}

TEST_F(ElevationLoaderTest, ResampledPostsLieWithinTheResamplingError) {
  const auto file = WriteUtm();
  double worst[2] = {0, 0};
  for (Resampling m : {Resampling::kBilinear, Resampling::kCubic}) {
    ElevationSource s{.file = file, .spacing_m = 7.0, .resampling = m};
    const ElevationLayout layout = ProbeElevation(s);
    EXPECT_EQ(layout.posts_x, 1000 / 7 + 1);
    const HeightGrid g = LoadElevation(s, layout);
    for (int j = 0; j < g.posts_z(); ++j) {
      for (int i = 0; i < g.posts_x(); ++i) {
        const double e = kE0 + 5 + 7.0 * i, n = kN0 + 5 + 7.0 * j;
        const double err = std::abs(g.post(i, j) - UtmSurface(e, n));
        ASSERT_LE(err, kUtmBoundM) << ResamplingName(m) << " post " << i << ", " << j;
        worst[static_cast<int>(m)] = std::max(worst[static_cast<int>(m)], err);
      }
    }
  }
  EXPECT_GT(worst[0], 0.0);
  // Cubic is third-order accurate: on a smooth surface it does better than bilinear.
  EXPECT_LT(worst[1], worst[0]);
}

TEST_F(ElevationLoaderTest, WindowInTheFilesCrs) {
  ElevationSource s{.file = WriteUtm(),
                    .area_kind = AreaKind::kFileCrs,
                    .area = {kE0 + 100, kN0 + 200, kE0 + 600, kN0 + 500}};
  const ElevationLayout layout = ProbeElevation(s);
  EXPECT_EQ(layout.posts_x, 51);
  EXPECT_EQ(layout.posts_z, 31);
  EXPECT_DOUBLE_EQ(layout.georeference->x0(), kE0 + 100);
  EXPECT_DOUBLE_EQ(layout.georeference->z0(), kN0 + 200);
  EXPECT_LT(static_cast<int64_t>(layout.window_cols) * layout.window_rows, 101 * 80 / 2);
  const HeightGrid g = LoadElevation(s, layout);
  for (int j = 0; j < g.posts_z(); ++j) {
    for (int i = 0; i < g.posts_x(); ++i) {
      ASSERT_NEAR(g.post(i, j), UtmSurface(kE0 + 100 + 10 * i, kN0 + 200 + 10 * j), kUtmBoundM);
    }
  }
  s.area = {kE0 - 50, kN0 + 200, kE0 + 600, kN0 + 500};
  EXPECT_NE(ErrorOf([&] { ProbeElevation(s); }).find("reaches beyond the file's data"),
            std::string::npos);
}

TEST_F(ElevationLoaderTest, WindowInLatLonOnAUtmFile) {
  double south = 0, west = 0, north = 0, east = 0;
  GeographicLib::UTMUPS::Reverse(33, true, kE0 + 200, kN0 + 200, south, west);
  GeographicLib::UTMUPS::Reverse(33, true, kE0 + 800, kN0 + 600, north, east);
  ElevationSource s{
      .file = WriteUtm(), .area_kind = AreaKind::kLonLat, .area = {west, south, east, north}};
  const ElevationLayout layout = ProbeElevation(s);
  const HeightGrid g = LoadElevation(s, layout);
  // The grid lies inside the box and fills most of it (the box is a little skew in UTM).
  for (auto [x, z] : {std::pair{0.0, 0.0}, std::pair{g.size_x_m(), g.size_z_m()}}) {
    const GeodeticPoint p = layout.georeference->ToGeodetic(x, 0, z);
    EXPECT_GE(p.latitude_deg, south - 1e-9);
    EXPECT_LE(p.latitude_deg, north + 1e-9);
    EXPECT_GE(p.longitude_deg, west - 1e-9);
    EXPECT_LE(p.longitude_deg, east + 1e-9);
  }
  EXPECT_GT(g.size_x_m(), 550.0);
  EXPECT_GT(g.size_z_m(), 350.0);
  for (int j = 0; j < g.posts_z(); j += 3) {
    for (int i = 0; i < g.posts_x(); i += 3) {
      const double e = layout.georeference->x0() + 10.0 * i;
      const double n = layout.georeference->z0() + 10.0 * j;
      ASSERT_NEAR(g.post(i, j), UtmSurface(e, n), kUtmBoundM);
    }
  }
}

// Lat/lon: the posts are laid in the plane tangent at the area's centre; each post's latitude and
// longitude (by the georeference) gives the formula's value.
constexpr double kLon0 = 8.0, kLat0 = 47.0, kWaveDeg = 0.02, kPixelDeg = 0.0005;
double LonLatSurface(double lon, double lat) {
  return 300.0 + kAmplitudeM * std::sin(2 * kPi * (lon - kLon0) / kWaveDeg) *
                     std::cos(2 * kPi * (lat - kLat0) / kWaveDeg);
}

TEST_F(ElevationLoaderTest, LatLonGeoTiffInTheTangentPlaneAtTheCentre) {
  TestRaster r;
  r.epsg = 4326;
  r.cols = 60;
  r.rows = 40;
  r.geotransform = {kLon0, kPixelDeg, 0, kLat0 + 40 * kPixelDeg, 0, -kPixelDeg};
  r.surface = LonLatSurface;
  WriteTestRaster(dir_ / "ll.tif", r);
  ElevationSource s{.file = dir_ / "ll.tif"};
  const ElevationLayout layout = ProbeElevation(s);
  EXPECT_FALSE(layout.local_is_file_crs);
  // The file's spacing: the pixel's smaller side, east-west (0.0005 deg of longitude at 47 N).
  EXPECT_NEAR(layout.spacing_m, 0.0005 * 111320 * std::cos(47.01 * kPi / 180), 0.5);
  const HeightGrid g = LoadElevation(s, layout);
  const GroundGeoreference& geo = *layout.georeference;
  const double bound = BilinearBound(kPixelDeg, kAmplitudeM * std::pow(2 * kPi / kWaveDeg, 2));
  for (int j = 0; j < g.posts_z(); ++j) {
    for (int i = 0; i < g.posts_x(); ++i) {
      const GeodeticPoint p = geo.ToGeodetic(i * g.spacing_m(), 0, j * g.spacing_m());
      ASSERT_NEAR(g.post(i, j), LonLatSurface(p.longitude_deg, p.latitude_deg), bound)
          << i << ", " << j;
    }
  }
  // The plane is east-north-up at the centre: GeographicLib's local frame there agrees.
  const GeodeticPoint centre = geo.ToGeodetic(-geo.x0(), 0, -geo.z0());
  EXPECT_NEAR(centre.latitude_deg, kLat0 + 0.01, 1e-3);
  const GeographicLib::LocalCartesian enu(centre.latitude_deg, centre.longitude_deg, 0);
  for (auto [x, z] :
       {std::pair{0.0, 0.0}, std::pair{g.size_x_m(), g.size_z_m()}, std::pair{g.size_x_m(), 0.0}}) {
    const GeodeticPoint p = geo.ToGeodetic(x, 0, z);
    double e = 0, n = 0, u = 0;
    enu.Forward(p.latitude_deg, p.longitude_deg, 0, e, n, u);
    EXPECT_NEAR(e, geo.x0() + x, 1e-3);
    EXPECT_NEAR(n, geo.z0() + z, 1e-3);
  }
}

TEST_F(ElevationLoaderTest, DtedCell) {
  // DTED level 0: a 1 deg cell of 121 x 121 posts, 30 arc seconds apart, whole metres.
  constexpr double kStep = 30.0 / 3600.0;
  const auto surface = [](double lon, double lat) {
    return 500.0 +
           200.0 * std::sin(2 * kPi * (lon - 8.0) / 0.5) * std::cos(2 * kPi * (lat - 47.0) / 0.5);
  };
  TestRaster r;
  r.driver = "DTED";
  r.epsg = 4326;
  r.cols = 121;
  r.rows = 121;
  r.geotransform = {8.0 - kStep / 2, kStep, 0, 48.0 + kStep / 2, 0, -kStep};
  r.surface = surface;
  r.integer = true;
  WriteTestRaster(dir_ / "n47.dt0", r);
  ElevationSource s{.file = dir_ / "n47.dt0"};
  const ElevationLayout layout = ProbeElevation(s);
  EXPECT_EQ(layout.driver, "DTED");
  const HeightGrid g = LoadElevation(s, layout);
  EXPECT_GT(g.posts_x(), 100);
  const double bound = BilinearBound(kStep, 200.0 * std::pow(2 * kPi / 0.5, 2)) + 0.5;
  for (int j = 0; j < g.posts_z(); ++j) {
    for (int i = 0; i < g.posts_x(); ++i) {
      const GeodeticPoint p =
          layout.georeference->ToGeodetic(i * g.spacing_m(), 0, j * g.spacing_m());
      ASSERT_NEAR(g.post(i, j), surface(p.longitude_deg, p.latitude_deg), bound) << i << ", " << j;
    }
  }
}

TEST_F(ElevationLoaderTest, NodataIsAnErrorNamingHowManyAndWhere) {
  ElevationSource s{.file = WriteUtm(-32767.0, {{10, 79}, {50, 40}})};
  const ElevationLayout layout = ProbeElevation(s);
  const std::string e = ErrorOf([&] { LoadElevation(s, layout); });
  // Pixel (10, 79) is post (10, 0); (50, 40) is post (50, 39). Exactly at pixel centres only the
  // hole itself is read.
  EXPECT_NE(e.find("2 of the 101 x 80 posts have no data"), std::string::npos) << e;
  EXPECT_NE(e.find("post (10, 0) at x 100 m z 0 m (file CRS 500105.000000, 5200005.000000)"),
            std::string::npos)
      << e;
  EXPECT_NE(e.find("post (50, 39)"), std::string::npos) << e;
  EXPECT_NE(e.find("nodata_fill"), std::string::npos) << e;

  s.nodata_fill = NodataFill::kConstant;
  s.nodata_fill_m = 12.5;
  HeightGrid g = LoadElevation(s, layout);
  EXPECT_EQ(g.post(10, 0), 12.5f);
  EXPECT_EQ(g.post(50, 39), 12.5f);
  s.nodata_fill = NodataFill::kNearest;
  g = LoadElevation(s, layout);
  // The nearest post with data is a neighbour (the first reached, in scan order: (9, 0)).
  EXPECT_EQ(g.post(10, 0), g.post(9, 0));
  EXPECT_NE(g.post(50, 39), -32767.0f);
  EXPECT_NEAR(g.post(50, 39), UtmSurface(kE0 + 505, kN0 + 395), 1.0);
}

TEST_F(ElevationLoaderTest, UnreadableFileNamesItAndGdalsMessage) {
  const auto path = dir_ / "junk.tif";
  std::ofstream(path) << "not a raster";
  ElevationSource s{.file = path};
  const std::string e = ErrorOf([&] { ProbeElevation(s); });
  EXPECT_NE(e.find(path.string()), std::string::npos) << e;
  EXPECT_NE(e.find("not recognized as a supported file format"), std::string::npos) << e;
  s.file = dir_ / "absent.tif";
  EXPECT_NE(ErrorOf([&] { ProbeElevation(s); }).find("No such file"), std::string::npos);
}

TEST_F(ElevationLoaderTest, NoGeoreferenceIsAnError) {
  TestRaster r;
  r.cols = r.rows = 20;
  r.geotransform = {0, 1, 0, 0, 0, -1};
  r.surface = [](double, double) { return 1.0; };
  r.georeferenced = false;
  WriteTestRaster(dir_ / "plain.tif", r);
  const std::string e = ErrorOf([&] { ProbeElevation({.file = dir_ / "plain.tif"}); });
  EXPECT_NE(e.find("no georeference"), std::string::npos) << e;
  EXPECT_NE(e.find("20 x 20 pixels"), std::string::npos) << e;
}

TEST_F(ElevationLoaderTest, TooLargeForTheMemoryAllowedIsAnErrorBeforeReading) {
  ElevationSource s{.file = WriteUtm(), .max_load_bytes = 100000};
  const std::string e = ErrorOf([&] { ProbeElevation(s); });
  EXPECT_NE(e.find("101 x 80 posts from 101 x 80 pixels"), std::string::npos) << e;
  EXPECT_NE(e.find("max_load_mb"), std::string::npos) << e;
  s.spacing_m = 0.05;  // 20000 posts a side
  EXPECT_NE(ErrorOf([&] { ProbeElevation(s); }).find("a side must hold 2 to 16385 posts"),
            std::string::npos);
}

}  // namespace
}  // namespace dt
